/*
 * codegen_fmi_core.h -- one FMU instance of a mechanism, whichever version of FMI the host
 * speaks: its variables by value reference (codegen_fmi.h's layout), its states and their
 * derivatives (Model Exchange), its steps with the library's own integrator
 * (Co-Simulation). codegen_fmi2.c and codegen_fmi3.c are thin front ends over it.
 *
 * Every function returns 0, or nonzero after logging why (an error in FMI's terms).
 */
#ifndef CODEGEN_FMI_CORE_H
#define CODEGEN_FMI_CORE_H

#include <stddef.h>

#include "codegen_fmi.h"

#ifdef __cplusplus
extern "C" {
#endif

/* How an instance reports: status 0 (OK) or 3 (error, the value of fmi2Error and fmi3Error). */
#define CODEGEN_FMI_OK 0
#define CODEGEN_FMI_ERROR 3
typedef void (*codegen_fmi_report)(void *host, const char *instance, int status,
                                   const char *category, const char *message);

typedef struct codegen_fmi_memory {
    void *(*allocate)(size_t count, size_t size);  /* zeroed, as calloc */
    void (*release)(void *memory);
} codegen_fmi_memory;

typedef struct codegen_fmi_instance codegen_fmi_instance;

/* A new instance of the model (NULL where memory runs out, or guid is not the model's). */
codegen_fmi_instance *codegen_fmi_new(const char *name, const char *guid, int cosimulation,
                                      int logging, codegen_fmi_memory memory,
                                      codegen_fmi_report report, void *host);
void codegen_fmi_free(codegen_fmi_instance *c);
void *codegen_fmi_host(const codegen_fmi_instance *c);   /* the host pointer it was made with */
void codegen_fmi_set_logging(codegen_fmi_instance *c, int logging);
/* An error in the log, from a front end. */
int codegen_fmi_fail(codegen_fmi_instance *c, const char *format, ...);

void codegen_fmi_setup(codegen_fmi_instance *c, int tolerance_defined, double tolerance,
                       double start);
int codegen_fmi_exit_initialisation(codegen_fmi_instance *c);  /* the parameters checked */
void codegen_fmi_terminate(codegen_fmi_instance *c);
void codegen_fmi_reset(codegen_fmi_instance *c);

int codegen_fmi_get(codegen_fmi_instance *c, const unsigned *vr, size_t n, double *values);
int codegen_fmi_set(codegen_fmi_instance *c, const unsigned *vr, size_t n, const double *values);

/* Model Exchange: 2 n_dof states (theta, then theta_d). */
size_t codegen_fmi_states(const codegen_fmi_instance *c);
void codegen_fmi_set_time(codegen_fmi_instance *c, double time);
double codegen_fmi_time(const codegen_fmi_instance *c);
int codegen_fmi_set_states(codegen_fmi_instance *c, const double *x, size_t n);
int codegen_fmi_get_states(codegen_fmi_instance *c, double *x, size_t n);
int codegen_fmi_derivatives(codegen_fmi_instance *c, double *dx, size_t n);

/* Co-Simulation: from now to now + step. */
int codegen_fmi_step(codegen_fmi_instance *c, double now, double step);

#ifdef __cplusplus
}
#endif

#endif /* CODEGEN_FMI_CORE_H */
