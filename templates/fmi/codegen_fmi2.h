/*
 * codegen_fmi2.h -- what the FMI 2.0 glue (codegen_fmi2.c, written once) needs from one
 * mechanism's library: a descriptor of plain functions over its parameters as an array of
 * doubles, which the small generated part of each FMU (NAME_fmi2.c) fills in.
 *
 * The FMU's variables, by value reference:
 *   [0, n_params)           the parameters (tunable)
 *   n_params + 0, + 1       the states: theta [rad], theta_d [rad/s]
 *   n_params + 2, + 3       their derivatives: der(theta) = theta_d, der(theta_d) = theta_dd
 *   n_params + 4 + i        input i, added to the load parameter loads[i] (0 by default)
 *   after the inputs        the outputs (points, energies: NAME_fmi2.c's order)
 *
 * Plain C99; no allocation of its own: an instance's memory comes from the FMI callbacks.
 */
#ifndef CODEGEN_FMI2_H
#define CODEGEN_FMI2_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct codegen_fmi2_model {
    const char *guid;               /* the modelDescription.xml's */
    int n_params;
    const double *defaults;         /* each parameter's start value (the model's example) */
    int n_loads;                    /* inputs */
    const int *loads;               /* the parameter each input is added to */
    int n_outputs;
    size_t simulation_size;         /* bytes of an integration in progress (co-simulation) */
    /* Each returns the library's status: 0, or what status_message explains. */
    int (*check)(const double *params);
    int (*acceleration)(const double *params, double theta, double theta_d, double *theta_dd);
    int (*outputs)(const double *params, double theta, double theta_d, double *out);
    int (*start)(void *simulation, const double *params, double t0, double theta,
                 double theta_d, double rtol);   /* rtol <= 0: the library's default */
    int (*advance)(void *simulation, double t, double *theta, double *theta_d);
    const char *(*status_message)(int status);
} codegen_fmi2_model;

/* The FMU's model: defined by its generated part. */
extern const codegen_fmi2_model codegen_fmi2_the_model;

#ifdef __cplusplus
}
#endif

#endif /* CODEGEN_FMI2_H */
