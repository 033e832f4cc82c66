/* A driver for runtime/codegen_boxes.c, used by tests/runtime_c/test_boxes_runtime.py: one
 * command per line on stdin, one answer line per command on stdout, numbers as C99 hex
 * floats both ways. The work array and the results are allocated here with exactly the sizes
 * the header gives, so that a sanitizer build catches any access beyond them.
 *
 *   solve PROBLEM N P0 P1 P2 P3 P4 P5 LO(N) HI(N) CAPACITY
 *       -> STATUS COUNT, then per result KIND LO(N) HI(N) POINT(N)
 *   misuse -> the statuses of calls with n < 1, a NULL pointer and a reversed box
 *
 * Problems (G and its Jacobian enclosed in interval arithmetic):
 *   circle     n = 2: (x^2 + y^2 - P0^2, x - P1 y)
 *   pendulum   n = 2: two bars on torsional springs, the double pendulum's statics:
 *              (k1 (t1 - a1) - k2 (t2 - t1 - a2) + c1 cos t1, k2 (t2 - t1 - a2) + c2 cos t2)
 *              with k1, k2, a1, a2, c1, c2 = P0..P5
 *   double     n = 2: (x^2 - P0, y - P1): a double zero at (0, P1) where P0 = 0
 *   pole       n = 2: (1/x - P0, y): G undefined at x = 0
 *   none       n = 2: (x^2 + y^2 + 1, x): no zero
 *   shift      n = N: (x_i - P0 - i P1): one zero, set on a split plane by the test
 *   cyclic     n = 3: (x - y^2, y - z^2, z - x^2): zeros (0, 0, 0) and (1, 1, 1)
 */
#include "codegen_boxes.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_N 6

typedef struct problem {
    char name[16];
    int n;
    codegen_real p[6];
} problem;

static codegen_iv point(codegen_real x)
{
    return codegen_iv_point(x);
}

static codegen_iv sq(codegen_iv x)
{
    return codegen_iv_pow(x, 2);
}

static int enclose(const void *context, const codegen_iv *x, codegen_iv *g, codegen_iv *j, unsigned *flags)
{
    const problem *pr = (const problem *)context;
    const codegen_real *p = pr->p;
    int i, k;
    if (strcmp(pr->name, "circle") == 0) {
        g[0] = codegen_iv_sub(codegen_iv_add(sq(x[0]), sq(x[1])), point(p[0] * p[0]));
        g[1] = codegen_iv_sub(x[0], codegen_iv_mul(point(p[1]), x[1]));
        if (j != NULL) {
            j[0] = codegen_iv_mul(point(2), x[0]);
            j[1] = codegen_iv_mul(point(2), x[1]);
            j[2] = point(1);
            j[3] = point(-p[1]);
        }
    } else if (strcmp(pr->name, "pendulum") == 0) {
        const codegen_iv twist = codegen_iv_sub(codegen_iv_sub(x[1], x[0]), point(p[3]));
        const codegen_iv spring = codegen_iv_mul(point(p[1]), twist);
        g[0] = codegen_iv_add(codegen_iv_sub(codegen_iv_mul(point(p[0]), codegen_iv_sub(x[0], point(p[2]))), spring),
                              codegen_iv_mul(point(p[4]), codegen_iv_cos(x[0])));
        g[1] = codegen_iv_add(spring, codegen_iv_mul(point(p[5]), codegen_iv_cos(x[1])));
        if (j != NULL) {
            j[0] = codegen_iv_sub(point(p[0] + p[1]), codegen_iv_mul(point(p[4]), codegen_iv_sin(x[0])));
            j[1] = point(-p[1]);
            j[2] = point(-p[1]);
            j[3] = codegen_iv_sub(point(p[1]), codegen_iv_mul(point(p[5]), codegen_iv_sin(x[1])));
        }
    } else if (strcmp(pr->name, "double") == 0) {
        g[0] = codegen_iv_sub(sq(x[0]), point(p[0]));
        g[1] = codegen_iv_sub(x[1], point(p[1]));
        if (j != NULL) {
            j[0] = codegen_iv_mul(point(2), x[0]);
            j[1] = j[2] = point(0);
            j[3] = point(1);
        }
    } else if (strcmp(pr->name, "pole") == 0) {
        g[0] = codegen_iv_sub(codegen_iv_div(point(1), x[0], flags), point(p[0]));
        g[1] = x[1];
        if (j != NULL) {
            j[0] = codegen_iv_neg(codegen_iv_div(point(1), sq(x[0]), flags));
            j[1] = j[2] = point(0);
            j[3] = point(1);
        }
    } else if (strcmp(pr->name, "none") == 0) {
        g[0] = codegen_iv_add(codegen_iv_add(sq(x[0]), sq(x[1])), point(1));
        g[1] = x[0];
        if (j != NULL) {
            j[0] = codegen_iv_mul(point(2), x[0]);
            j[1] = codegen_iv_mul(point(2), x[1]);
            j[2] = point(1);
            j[3] = point(0);
        }
    } else if (strcmp(pr->name, "shift") == 0) {
        for (i = 0; i < pr->n; ++i) {
            g[i] = codegen_iv_sub(x[i], codegen_iv_add(point(p[0]), codegen_iv_mul(point((codegen_real)i), point(p[1]))));
            for (k = 0; k < pr->n && j != NULL; ++k) {
                j[i * pr->n + k] = point(i == k ? 1 : 0);
            }
        }
    } else if (strcmp(pr->name, "cyclic") == 0) {
        for (i = 0; i < 3; ++i) {
            g[i] = codegen_iv_sub(x[i], sq(x[(i + 1) % 3]));
            for (k = 0; k < 3 && j != NULL; ++k) {
                j[i * 3 + k] = k == i ? point(1) : k == (i + 1) % 3 ? codegen_iv_mul(point(-2), x[k]) : point(0);
            }
        }
    } else {
        return 99;
    }
    return 0;
}

static codegen_real next(void)
{
    char word[64];
    if (scanf("%63s", word) != 1) {
        exit(2);
    }
    return (codegen_real)strtod(word, NULL);
}

static void *allocate(size_t bytes)
{
    void *p = malloc(bytes);
    if (p == NULL) {
        exit(5);
    }
    return p;
}

static void solve(void)
{
    problem pr;
    codegen_real lo[MAX_N], hi[MAX_N];
    codegen_boxes out;
    codegen_real *work;
    int i, r, status, capacity;
    if (scanf("%15s", pr.name) != 1) {
        exit(2);
    }
    pr.n = (int)next();
    if (pr.n < 1 || pr.n > MAX_N) {
        exit(3);
    }
    for (i = 0; i < 6; ++i) {
        pr.p[i] = next();
    }
    for (i = 0; i < pr.n; ++i) {
        lo[i] = next();
    }
    for (i = 0; i < pr.n; ++i) {
        hi[i] = next();
    }
    capacity = (int)next();
    out.capacity = capacity;
    out.lo = (codegen_real *)allocate(sizeof(codegen_real) * (size_t)(capacity * pr.n));
    out.hi = (codegen_real *)allocate(sizeof(codegen_real) * (size_t)(capacity * pr.n));
    out.point = (codegen_real *)allocate(sizeof(codegen_real) * (size_t)(capacity * pr.n));
    out.kind = (codegen_box_kind *)allocate(sizeof(codegen_box_kind) * (size_t)capacity);
    work = (codegen_real *)allocate(sizeof(codegen_real) * (size_t)CODEGEN_BOXES_WORK(pr.n));
    status = codegen_isolate_boxes(pr.n, enclose, &pr, lo, hi, &out, work);
    printf("%d %d", status, out.count);
    for (r = 0; r < out.count; ++r) {
        printf(" %d", (int)out.kind[r]);
        for (i = 0; i < pr.n; ++i) {
            printf(" %a", (double)out.lo[r * pr.n + i]);
        }
        for (i = 0; i < pr.n; ++i) {
            printf(" %a", (double)out.hi[r * pr.n + i]);
        }
        for (i = 0; i < pr.n; ++i) {
            printf(" %a", (double)out.point[r * pr.n + i]);
        }
    }
    free(out.lo);
    free(out.hi);
    free(out.point);
    free(out.kind);
    free(work);
}

static void misuse(void)
{
    problem pr;
    codegen_real lo[2] = {0, 0}, hi[2] = {1, 1}, reversed[2] = {1, -1}, buffer[64];
    codegen_box_kind kind[4];
    codegen_boxes out;
    static codegen_real work[CODEGEN_BOXES_WORK(2)];
    strcpy(pr.name, "circle");
    pr.n = 2;
    out.capacity = 4;
    out.lo = buffer;
    out.hi = buffer + 8;
    out.point = buffer + 16;
    out.kind = kind;
    printf("%d %d %d", codegen_isolate_boxes(0, enclose, &pr, lo, hi, &out, work),
           codegen_isolate_boxes(2, enclose, &pr, lo, NULL, &out, work),
           codegen_isolate_boxes(2, enclose, &pr, lo, reversed, &out, work));
}

int main(void)
{
    char command[32];
    while (scanf("%31s", command) == 1) {
        if (strcmp(command, "solve") == 0) {
            solve();
        } else if (strcmp(command, "misuse") == 0) {
            misuse();
        } else {
            return 4;
        }
        printf("\n");
        fflush(stdout);
    }
    return 0;
}
