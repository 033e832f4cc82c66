/* Link the generated library into a program of your own:
 *   cc -std=c99 -Igenerated/doughty -Igenerated/runtime examples/minimal.c \
 *      generated/doughty/doughty*.c generated/runtime/codegen*.c -lm -o minimal
 */
#include <stdio.h>

#include "doughty.h"

int main(void)
{
    const doughty_params table2 = {0.18, 0.9, 0.135, 0.194, 0.143, 9.124,
                                   3500.0, 875.0, 0.15, 110.0, 9.81};
    doughty_analysis analysis;
    int i;
    doughty_status status = doughty_analyze(&table2, &analysis);
    if (status != DOUGHTY_OK) {
        fprintf(stderr, "doughty_analyze: %s\n", doughty_status_message(status));
        return 1;
    }
    for (i = 0; i < analysis.n_roots; ++i) {
        const doughty_equilibrium *e = &analysis.roots[i];
        printf("theta_E = %9.4f deg  %-10s  K_EQ = %10.4f N m\n", e->theta * 57.29577951308232,
               e->genuine ? "genuine" : "extraneous", e->K);
    }
    return 0;
}
