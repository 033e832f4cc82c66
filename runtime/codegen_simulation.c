/*
 * codegen_simulation.c -- the time response of the reduced equation of motion,
 * thetaddot = f(theta, thetadot), of any mechanism described by a codegen_model, by the
 * runtime's integrator (codegen_ode.c) on the model's unchecked acceleration kernel: the
 * inputs are validated once per call, never per evaluation. Hand-written (not generated).
 */
#include "codegen_model.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

/* The state vector: (theta [rad], thetadot [rad/s]). */
#define DIMENSION 2

/* What the right-hand side needs: the model, the validated parameters and the sign choice
 * of the assembly roots the motion is on. */
typedef struct motion {
    const codegen_model *model;
    const void *params;
    unsigned signs;
} motion;

/* y' = (thetadot, thetaddot) */
static void rhs(const void *context, codegen_real t, const codegen_real *y, codegen_real *rate)
{
    const motion *m = (const motion *)context;
    (void)t; /* autonomous: the loads are constant */
    rate[0] = y[1];
    rate[1] = m->model->angular_acceleration(m->params, m->signs, y[0], y[1]);
}

static int status_of(const codegen_model *model, codegen_ode_status status)
{
    switch (status) {
    case CODEGEN_ODE_OK:
        return CODEGEN_OK;
    case CODEGEN_ODE_BAD_INPUT:
        return CODEGEN_ERR_ARGUMENT;
    case CODEGEN_ODE_BUDGET:
        return CODEGEN_ERR_STEP_BUDGET;
    case CODEGEN_ODE_STEP_UNDERFLOW:
        return CODEGEN_ERR_STEP_SIZE;
    case CODEGEN_ODE_NONFINITE:
        return model->acceleration_failure;
    }
    return CODEGEN_ERR_ARGUMENT;
}

/* The parts of a NAME_simulation. */
typedef struct parts {
    void *params;
    codegen_ode_options *options;
    codegen_ode_state *state;
    codegen_real *work;
    unsigned *signs;
} parts;

static parts parts_of(const codegen_model *model, void *simulation)
{
    parts p;
    p.params = (char *)simulation + model->simulation.params;
    p.options = (codegen_ode_options *)(void *)((char *)simulation + model->simulation.options);
    p.state = (codegen_ode_state *)(void *)((char *)simulation + model->simulation.state);
    p.work = (codegen_real *)(void *)((char *)simulation + model->simulation.work);
    p.signs = (unsigned *)(void *)((char *)simulation + model->simulation.signs);
    return p;
}

int codegen_simulation_start(const codegen_model *model, void *simulation, const void *params,
                             codegen_real t0, codegen_real theta0, codegen_real theta_d0,
                             const codegen_ode_options *options)
{
    const codegen_real y0[DIMENSION] = {theta0, theta_d0};
    motion m;
    parts p;
    int status;
    if (simulation == NULL || params == NULL) {
        return CODEGEN_ERR_NULL_POINTER;
    }
    status = model->check_params(params);
    if (status != CODEGEN_OK) {
        return status;
    }
    if (!isfinite(t0) || !isfinite(theta0) || !isfinite(theta_d0)) {
        return CODEGEN_ERR_NONFINITE;
    }
    /* the mode the model declares at theta0: a motion stays on its sign choice (the closed
     * form is smooth along it until a limit position, where the motion is singular anyway) */
    status = codegen_signs_at(model, params, theta0, model->acceleration_failure, &m.signs);
    if (status != CODEGEN_OK) {
        return status;
    }
    p = parts_of(model, simulation);
    memcpy(p.params, params, model->params_size);
    *p.options = options != NULL ? *options : codegen_ode_defaults();
    *p.signs = m.signs;
    m.model = model;
    m.params = p.params;
    return status_of(model, codegen_ode_start(rhs, &m, DIMENSION, t0, y0, p.options,
                                              p.state, p.work));
}

int codegen_simulation_advance(const codegen_model *model, void *simulation,
                               const codegen_real *times, size_t n_times, codegen_real *theta,
                               codegen_real *theta_d, size_t *reached)
{
    size_t i;
    int status;
    motion m;
    parts p;
    if (reached != NULL) {
        *reached = 0;
    }
    if (simulation == NULL || (n_times > 0 && (times == NULL || theta == NULL || theta_d == NULL))) {
        return CODEGEN_ERR_NULL_POINTER;
    }
    p = parts_of(model, simulation);
    status = model->check_params(p.params);
    if (status != CODEGEN_OK) {
        return status;
    }
    for (i = 0; i < n_times; ++i) {
        if (!isfinite(times[i])) {
            return CODEGEN_ERR_NONFINITE;
        }
    }
    if (p.state->failed != CODEGEN_ODE_OK) {
        return status_of(model, p.state->failed);
    }
    for (i = 0; i < n_times; ++i) {
        if (times[i] < (i == 0 ? p.state->t_prev : times[i - 1])) {
            return CODEGEN_ERR_ARGUMENT;
        }
    }
    m.model = model;
    m.params = p.params;
    m.signs = *p.signs;
    if (m.signs >= (unsigned)model->n_modes) {
        return CODEGEN_ERR_ARGUMENT;   /* not a simulation _start made */
    }
    for (i = 0; i < n_times; ++i) {
        codegen_real y[DIMENSION];
        status = status_of(model, codegen_ode_advance(rhs, &m, p.options, p.state,
                                                      p.work, &times[i], 1, y, NULL));
        if (status != CODEGEN_OK) {
            return status;
        }
        theta[i] = y[0];
        theta_d[i] = y[1];
        if (reached != NULL) {
            *reached = i + 1;
        }
    }
    return CODEGEN_OK;
}

int codegen_simulate(const codegen_model *model, void *simulation, const void *params,
                     codegen_real theta0, codegen_real theta_d0, const codegen_real *times,
                     size_t n_times, const codegen_ode_options *options, codegen_real *theta,
                     codegen_real *theta_d, size_t *reached)
{
    int status;
    if (reached != NULL) {
        *reached = 0;
    }
    if (params == NULL || times == NULL || theta == NULL || theta_d == NULL) {
        return CODEGEN_ERR_NULL_POINTER;
    }
    if (n_times < 1) {
        return CODEGEN_ERR_ARGUMENT;
    }
    status = codegen_simulation_start(model, simulation, params, times[0], theta0, theta_d0, options);
    if (status != CODEGEN_OK) {
        return status;
    }
    return codegen_simulation_advance(model, simulation, times, n_times, theta, theta_d, reached);
}

int codegen_rk4_step(const codegen_model *model, const void *params, codegen_real h,
                     codegen_real theta, codegen_real theta_d, codegen_real *theta_next,
                     codegen_real *theta_d_next)
{
    const codegen_real y[DIMENSION] = {theta, theta_d};
    codegen_real work[CODEGEN_ODE_RK4_WORK(DIMENSION)], next[DIMENSION];
    motion m;
    int status;
    if (params == NULL || theta_next == NULL || theta_d_next == NULL) {
        return CODEGEN_ERR_NULL_POINTER;
    }
    status = model->check_params(params);
    if (status != CODEGEN_OK) {
        return status;
    }
    if (!isfinite(h) || !isfinite(theta) || !isfinite(theta_d)) {
        return CODEGEN_ERR_NONFINITE;
    }
    m.model = model;
    m.params = params;
    status = codegen_signs_at(model, params, theta, model->acceleration_failure, &m.signs);
    if (status != CODEGEN_OK) {
        return status;
    }
    status = status_of(model, codegen_ode_rk4_step(rhs, &m, DIMENSION, 0, y, h,
                                                   work, next));
    if (status == CODEGEN_OK) {
        *theta_next = next[0];
        *theta_d_next = next[1];
    }
    return status;
}
