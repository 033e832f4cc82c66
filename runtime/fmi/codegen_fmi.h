/*
 * codegen_fmi.h -- what the FMI glue (codegen_fmi_core.c, written once) needs from one
 * mechanism's library: a descriptor of plain functions over its parameters as an array of
 * doubles, which the small generated part of each FMU (NAME_fmi.c) fills in.
 *
 * The FMU's variables, by value reference, for n = n_dof coordinates:
 *   [0, n_params)                 the parameters (tunable)
 *   n_params + [0, n)             the states: the coordinates theta_k
 *   n_params + [n, 2n)            and their rates theta_d_k
 *   n_params + [2n, 4n)           their derivatives: der(theta_k) = theta_d_k, der(theta_d_k)
 *   n_params + 4n + i             input i, added to the load parameter loads[i] (0 by default)
 *   after the inputs              the outputs (points, energies: NAME_fmi.c's order)
 *   after the outputs             the time [s] (FMI 3.0's independent variable)
 *
 * Plain C99; an instance's memory is allocated once, when it is instantiated.
 */
#ifndef CODEGEN_FMI_H
#define CODEGEN_FMI_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct codegen_fmi_model {
    const char *guid;               /* the modelDescription.xml's */
    int n_dof;                      /* coordinates: 2 n_dof continuous states */
    int n_params;
    const double *defaults;         /* each parameter's start value (the model's example) */
    const double *initial;          /* the states' start values (2 n_dof: theta, theta_d) */
    int n_loads;                    /* inputs */
    const int *loads;               /* the parameter each input is added to */
    int n_outputs;
    size_t simulation_size;         /* bytes of an integration in progress (co-simulation) */
    /* Each returns the library's status: 0, or what status_message explains. */
    int (*check)(const double *params);
    /* at a state (theta, theta_d: n each): theta_dd (n), or the outputs */
    int (*acceleration)(const double *params, const double *theta, const double *theta_d,
                        double *theta_dd);
    int (*outputs)(const double *params, const double *theta, const double *theta_d, double *out);
    /* co-simulation: an integration from (theta, theta_d) at t0, advanced to t in place */
    int (*start)(void *simulation, const double *params, double t0, const double *theta,
                 const double *theta_d, double rtol);   /* rtol <= 0: the library's default */
    int (*advance)(void *simulation, double t, double *theta, double *theta_d);
    const char *(*status_message)(int status);
} codegen_fmi_model;

/* The FMU's model: defined by its generated part. */
extern const codegen_fmi_model codegen_fmi_the_model;

#ifdef __cplusplus
}
#endif

#endif /* CODEGEN_FMI_H */
