/* A driver for the integrator of runtime/codegen_ode.c, used by
 * tests/runtime_c/test_ode_runtime.py: one command per line on stdin, one answer line per
 * command on stdout. Doubles travel as C99 hex floats both ways (strtod reads them, %a prints them), so
 * nothing is rounded between C and Python.
 *
 *   solve PROBLEM A B RTOL ATOL H_MAX MAX_STEPS N Y0.. COUNT T..
 *       -> STATUS REACHED STEPS REJECTED EVALUATIONS T H Y(T_0).. Y(T_REACHED-1)..
 *   split SPLIT PROBLEM ...   the same integration started once and advanced in two calls
 *       (outputs [0, SPLIT) then the rest); the same answer line
 *   rk4 PROBLEM A B T H N Y..  -> STATUS Y_NEXT..
 *   misuse                    -> the statuses of calls with NULL pointers, n < 1 and an
 *       advance after a failure, in a fixed order
 *
 * Problems (parameters A, B):
 *   oscillator  x'' + 2 A B x' + B^2 x = 0 as y = (x, x'): damping ratio A, frequency B
 *   decay       y' = A y
 *   clock       y' = cos(A t) (time-dependent)
 *   rotation    y = (u, v, w): u' = A u - B v, v' = B u + A v, w' = -B w
 *   blowup      y' = y^2 (from y(0) = 1/A it is infinite at t = A)
 *   wall        y' = 1, but NaN for y > A (f undefined beyond a wall)
 *   nan         y' = NaN everywhere
 */
#include "codegen_ode.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_N 3
#define MAX_TIMES 16384

typedef struct problem {
    char name[16];
    double a, b;
} problem;

static void rhs(const void *context, double t, const double *y, double *dydt)
{
    const problem *p = (const problem *)context;
    if (strcmp(p->name, "oscillator") == 0) {
        dydt[0] = y[1];
        dydt[1] = -2.0 * p->a * p->b * y[1] - p->b * p->b * y[0];
    } else if (strcmp(p->name, "decay") == 0) {
        dydt[0] = p->a * y[0];
    } else if (strcmp(p->name, "clock") == 0) {
        dydt[0] = cos(p->a * t);
    } else if (strcmp(p->name, "rotation") == 0) {
        dydt[0] = p->a * y[0] - p->b * y[1];
        dydt[1] = p->b * y[0] + p->a * y[1];
        dydt[2] = -p->b * y[2];
    } else if (strcmp(p->name, "blowup") == 0) {
        dydt[0] = y[0] * y[0];
    } else if (strcmp(p->name, "wall") == 0) {
        dydt[0] = y[0] > p->a ? NAN : 1.0;
    } else {
        dydt[0] = NAN;
    }
}

static double number(void)
{
    char word[64];
    if (scanf("%63s", word) != 1) {
        exit(2);
    }
    return strtod(word, NULL);
}

static long integer(void)
{
    return (long)number();
}

static void read_problem(problem *p)
{
    if (scanf("%15s", p->name) != 1) {
        exit(2);
    }
    p->a = number();
    p->b = number();
}

static void read_vector(double *x, int *n, int max)
{
    int i;
    *n = (int)integer();
    if (*n > max) {
        exit(3);
    }
    for (i = 0; i < *n; ++i) {
        x[i] = number();
    }
}

/* Work and outputs on the heap, exactly as large as documented, so that AddressSanitizer
 * sees any access beyond them. */
static double *doubles(size_t count)
{
    double *block = (double *)malloc((count ? count : 1) * sizeof(double));
    if (block == NULL) {
        exit(4);
    }
    return block;
}

static void solve(size_t split)
{
    static double times[MAX_TIMES];
    double y0[MAX_N], *work, *out;
    codegen_ode_options options;
    codegen_ode_state state;
    problem p;
    int n, count, status;
    size_t reached = 0, i;
    read_problem(&p);
    options.rtol = number();
    options.atol = number();
    options.h_max = number();
    options.max_steps = integer();
    read_vector(y0, &n, MAX_N);
    read_vector(times, &count, MAX_TIMES);
    work = doubles((size_t)CODEGEN_ODE_WORK(n));
    out = doubles((size_t)count * (size_t)n);
    memset(&state, 0, sizeof state);
    if (split == 0) {
        status = codegen_ode_solve(rhs, &p, n, y0, times, (size_t)count, &options, &state, work,
                                   out, &reached);
    } else {
        size_t first = 0, second = 0;
        status = codegen_ode_start(rhs, &p, n, times[0], y0, &options, &state, work);
        if (status == CODEGEN_ODE_OK) {
            status = codegen_ode_advance(rhs, &p, &options, &state, work, times, split, out,
                                         &first);
        }
        if (status == CODEGEN_ODE_OK) {
            status = codegen_ode_advance(rhs, &p, &options, &state, work, times + split,
                                         (size_t)count - split, out + split * (size_t)n, &second);
        }
        reached = first + second;
    }
    printf("%d %lu %ld %ld %ld %a %a", status, (unsigned long)reached, state.steps,
           state.rejected, state.evaluations, state.t, state.h);
    for (i = 0; i < reached * (size_t)n; ++i) {
        printf(" %a", out[i]);
    }
    printf("\n");
    free(work);
    free(out);
}

static void rk4(void)
{
    double y[MAX_N], *work, t, h;
    problem p;
    int n, i, status;
    read_problem(&p);
    t = number();
    h = number();
    read_vector(y, &n, MAX_N);
    work = doubles((size_t)CODEGEN_ODE_RK4_WORK(n));
    status = codegen_ode_rk4_step(rhs, &p, n, t, y, h, work, y);
    printf("%d", status);
    for (i = 0; i < n; ++i) {
        printf(" %a", y[i]);
    }
    printf("\n");
    free(work);
}

static void misuse(void)
{
    const problem decay = {"decay", -1.0, 0.0}, wall = {"wall", 0.5, 0.0};
    const codegen_ode_options options = codegen_ode_defaults();
    double y0[1] = {1.0}, times[2] = {0.0, 1.0}, out[2], work[CODEGEN_ODE_WORK(1)];
    codegen_ode_state state;
    size_t reached = 99;
    int statuses[12], i;
    statuses[0] = codegen_ode_start(NULL, &decay, 1, 0.0, y0, &options, &state, work);
    statuses[1] = codegen_ode_start(rhs, &decay, 0, 0.0, y0, &options, &state, work);
    statuses[2] = codegen_ode_start(rhs, &decay, 1, 0.0, NULL, &options, &state, work);
    statuses[3] = codegen_ode_start(rhs, &decay, 1, 0.0, y0, NULL, &state, work);
    statuses[4] = codegen_ode_start(rhs, &decay, 1, 0.0, y0, &options, NULL, work);
    statuses[5] = codegen_ode_start(rhs, &decay, 1, 0.0, y0, &options, &state, NULL);
    statuses[6] = codegen_ode_solve(rhs, &decay, 1, y0, times, 0, &options, &state, work, out,
                                    &reached);
    statuses[7] = codegen_ode_start(rhs, &decay, 1, 0.0, y0, &options, &state, work);
    statuses[8] = codegen_ode_advance(rhs, &decay, &options, &state, work, NULL, 1, out, NULL);
    /* a failure is final: the wall stops it, and a later call returns the same status */
    statuses[9] = codegen_ode_solve(rhs, &wall, 1, y0 /* 1 > 0.5: NaN at once */, times, 2,
                                    &options, &state, work, out, &reached);
    statuses[10] = codegen_ode_advance(rhs, &wall, &options, &state, work, times, 1, out,
                                       &reached);
    statuses[11] = codegen_ode_rk4_step(rhs, &decay, 1, 0.0, y0, 0.1, NULL, out);
    for (i = 0; i < 12; ++i) {
        printf("%s%d", i ? " " : "", statuses[i]);
    }
    printf(" %lu\n", (unsigned long)reached);
}

int main(void)
{
    char command[16];
    while (scanf("%15s", command) == 1) {
        if (strcmp(command, "solve") == 0) {
            solve(0);
        } else if (strcmp(command, "split") == 0) {
            solve((size_t)integer());
        } else if (strcmp(command, "rk4") == 0) {
            rk4();
        } else if (strcmp(command, "misuse") == 0) {
            misuse();
        } else {
            return 2;
        }
        fflush(stdout);
    }
    return 0;
}
