/* A driver for runtime/codegen_modal.c, used by tests/runtime_c/test_modal_runtime.py: one
 * command per line on stdin, one answer line per command on stdout. Numbers travel as C99 hex
 * floats both ways (strtod reads them, %a prints them), so nothing is rounded between C and
 * Python; compiled with -DCODEGEN_FLOAT the library computes in float (inputs rounded once).
 * Each work array is allocated here with exactly the size its CODEGEN_*_WORK macro gives, so
 * that a sanitizer build catches any access beyond it.
 *
 *   modes N M.. K..            -> STATUS OMEGA_SQUARED(N) SHAPES(N*N, row-major)
 *   eigenvalues N M.. B.. K..  -> STATUS RE(2N) IM(2N)
 *   receptance N OMEGA M.. B.. K.. -> STATUS H_RE(N*N) H_IM(N*N)
 *   misuse                     -> the statuses of calls with NULL pointers and n < 1
 */
#include "codegen_modal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_N 8

static codegen_real next(void)
{
    char word[64];
    if (scanf("%63s", word) != 1) {
        exit(2);
    }
    return (codegen_real)strtod(word, NULL);
}

static int read_n(void)
{
    const int n = (int)next();
    if (n < 1 || n > MAX_N) {
        exit(3);
    }
    return n;
}

static void read_matrix(int n, codegen_real *a)
{
    int i;
    for (i = 0; i < n * n; ++i) {
        a[i] = next();
    }
}

static codegen_real *work_of(int size)
{
    codegen_real *work = (codegen_real *)malloc(sizeof(codegen_real) * (size_t)size);
    if (work == NULL) {
        exit(5);
    }
    return work;
}

static void print(const codegen_real *a, int count)
{
    int i;
    for (i = 0; i < count; ++i) {
        printf(" %a", (double)a[i]);
    }
}

int main(void)
{
    char command[32];
    static codegen_real m[MAX_N * MAX_N], b[MAX_N * MAX_N], k[MAX_N * MAX_N], x[MAX_N * MAX_N],
        y[MAX_N * MAX_N], w[2 * MAX_N], z[2 * MAX_N], one[64];
    codegen_real *work;
    while (scanf("%31s", command) == 1) {
        if (strcmp(command, "modes") == 0) {
            const int n = read_n();
            int status;
            read_matrix(n, m);
            read_matrix(n, k);
            work = work_of(CODEGEN_MODES_WORK(n));
            status = codegen_modes(n, m, k, w, x, work);
            free(work);
            printf("%d", status);
            print(w, n);
            print(x, n * n);
        } else if (strcmp(command, "eigenvalues") == 0) {
            const int n = read_n();
            int status;
            read_matrix(n, m);
            read_matrix(n, b);
            read_matrix(n, k);
            work = work_of(CODEGEN_DAMPED_EIGENVALUES_WORK(n));
            status = codegen_damped_eigenvalues(n, m, b, k, w, z, work);
            free(work);
            printf("%d", status);
            print(w, 2 * n);
            print(z, 2 * n);
        } else if (strcmp(command, "receptance") == 0) {
            const int n = read_n();
            const codegen_real omega = next();
            int status;
            read_matrix(n, m);
            read_matrix(n, b);
            read_matrix(n, k);
            work = work_of(CODEGEN_RECEPTANCE_WORK(n));
            status = codegen_receptance(n, m, b, k, omega, x, y, work);
            free(work);
            printf("%d", status);
            print(x, n * n);
            print(y, n * n);
        } else if (strcmp(command, "misuse") == 0) {
            m[0] = k[0] = 1;
            b[0] = 0;
            printf("%d %d %d %d %d %d", codegen_modes(0, m, k, w, x, one),
                   codegen_modes(1, m, NULL, w, x, one),
                   codegen_damped_eigenvalues(1, m, b, k, w, NULL, one),
                   codegen_damped_eigenvalues(-1, m, b, k, w, z, one),
                   codegen_receptance(1, m, b, k, 1, x, y, NULL),
                   codegen_receptance(1, m, b, k, (codegen_real)NAN, x, y, one));
        } else {
            return 4;
        }
        printf("\n");
        fflush(stdout);
    }
    return 0;
}
