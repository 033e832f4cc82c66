/*
 * codegen_fmi_core.c -- one FMU instance of a mechanism (codegen_fmi_core.h), written once for
 * every FMI version and every mechanism, over the descriptor of codegen_fmi.h.
 *
 * Model Exchange: the host integrates the states; their derivatives are the rates and the
 * library's accelerations. Co-Simulation: a step integrates with the library's own adaptive
 * Dormand-Prince 5(4) at the experiment's tolerance, one integration carried from each step
 * to the next (its step size and last stage kept: a run of steps is one integration over
 * their times, whatever the number of coordinates); a change of a parameter, an input or a
 * state restarts it from the current state (a value set to what it was is no change). A
 * state where the motion is not defined (a spring of zero length, a lost assembly) or a
 * parameter the library refuses is an error with the library's one-line reason in the log,
 * never a NaN; so is a state set to NaN or an infinity (refused, the state kept as it was).
 * Memory: allocated when the instance is made, released when it is freed; nothing between.
 */
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "codegen_fmi_core.h"

typedef enum { INSTANTIATED, INITIALISATION, RUNNING, TERMINATED, FAILED } phase;

struct codegen_fmi_instance {
    const codegen_fmi_model *model;
    codegen_fmi_memory memory;
    codegen_fmi_report report;
    void *host;
    char name[64];
    int cosimulation;
    phase phase;
    int logging;
    double time;
    double rtol;        /* the experiment's tolerance; 0: the library's default */
    double *x;          /* 2 n_dof: theta, then theta_d */
    double *theta_dd;   /* n_dof */
    double *params;     /* n_params: the parameters as set */
    double *inputs;     /* n_loads */
    double *applied;    /* n_params: the parameters with the inputs added */
    double *outputs;    /* n_outputs */
    void *simulation;   /* co-simulation: the integration in progress */
    int running;        /* whether *simulation holds the current state and parameters */
};

#define VR_STATES(m) ((unsigned)(m)->n_params)
#define N_STATES(m) (2u * (unsigned)(m)->n_dof)
#define VR_INPUTS(m) (VR_STATES(m) + 2u * N_STATES(m))
#define VR_OUTPUTS(m) (VR_INPUTS(m) + (unsigned)(m)->n_loads)
#define VR_TIME(m) (VR_OUTPUTS(m) + (unsigned)(m)->n_outputs)

static void say(const codegen_fmi_instance *c, int status, const char *category, const char *format,
                va_list args)
{
    char text[256];
    if (c->report == NULL || (status == CODEGEN_FMI_OK && !c->logging)) {
        return;
    }
    vsnprintf(text, sizeof text, format, args);
    c->report(c->host, c->name, status, category, text);
}

int codegen_fmi_fail(codegen_fmi_instance *c, const char *format, ...)
{
    va_list args;
    va_start(args, format);
    say(c, CODEGEN_FMI_ERROR, "logStatusError", format, args);
    va_end(args);
    return CODEGEN_FMI_ERROR;
}

/* An error with the library's reason for status (what failed: ``what``). */
static int failed(codegen_fmi_instance *c, int status, const char *what)
{
    return codegen_fmi_fail(c, "%s: %s (status %d)", what, c->model->status_message(status),
                            status);
}

static const double *applied(codegen_fmi_instance *c)
{
    int i;
    memcpy(c->applied, c->params, (size_t)c->model->n_params * sizeof(double));
    for (i = 0; i < c->model->n_loads; ++i) {
        c->applied[c->model->loads[i]] += c->inputs[i];
    }
    return c->applied;
}

static void *allocate(const codegen_fmi_instance *c, size_t count, size_t size)
{
    return count == 0 ? NULL : c->memory.allocate(count, size);
}

void codegen_fmi_free(codegen_fmi_instance *c)
{
    if (c == NULL) {
        return;
    }
    c->memory.release(c->params);
    c->memory.release(c->inputs);
    c->memory.release(c->applied);
    c->memory.release(c->outputs);
    c->memory.release(c->x);
    c->memory.release(c->theta_dd);
    c->memory.release(c->simulation);
    c->memory.release(c);
}

codegen_fmi_instance *codegen_fmi_new(const char *name, const char *guid, int cosimulation,
                                      int logging, codegen_fmi_memory memory,
                                      codegen_fmi_report report, void *host)
{
    const codegen_fmi_model *m = &codegen_fmi_the_model;
    codegen_fmi_instance *c;
    if (memory.allocate == NULL || memory.release == NULL) {
        return NULL;
    }
    c = (codegen_fmi_instance *)memory.allocate(1, sizeof(codegen_fmi_instance));
    if (c == NULL) {
        return NULL;
    }
    c->model = m;
    c->memory = memory;
    c->report = report;
    c->host = host;
    snprintf(c->name, sizeof c->name, "%s", name != NULL ? name : "");
    c->cosimulation = cosimulation;
    c->logging = logging;
    if (guid == NULL || strcmp(guid, m->guid) != 0) {
        codegen_fmi_fail(c, "instantiation: %s is not this FMU's token (%s)",
                         guid != NULL ? guid : "(none)", m->guid);
        memory.release(c);
        return NULL;
    }
    c->params = (double *)allocate(c, (size_t)m->n_params, sizeof(double));
    c->applied = (double *)allocate(c, (size_t)m->n_params, sizeof(double));
    c->inputs = (double *)allocate(c, (size_t)m->n_loads, sizeof(double));
    c->outputs = (double *)allocate(c, (size_t)m->n_outputs, sizeof(double));
    c->x = (double *)allocate(c, N_STATES(m), sizeof(double));
    c->theta_dd = (double *)allocate(c, (size_t)m->n_dof, sizeof(double));
    c->simulation = cosimulation ? allocate(c, 1, m->simulation_size) : NULL;
    if (c->params == NULL || c->applied == NULL || (m->n_loads > 0 && c->inputs == NULL)
        || (m->n_outputs > 0 && c->outputs == NULL) || c->x == NULL || c->theta_dd == NULL
        || (cosimulation && c->simulation == NULL)) {
        codegen_fmi_fail(c, "instantiation: out of memory");
        codegen_fmi_free(c);
        return NULL;
    }
    memcpy(c->params, m->defaults, (size_t)m->n_params * sizeof(double));
    memcpy(c->x, m->initial, N_STATES(m) * sizeof(double));
    return c;
}

void *codegen_fmi_host(const codegen_fmi_instance *c)
{
    return c->host;
}

void codegen_fmi_set_logging(codegen_fmi_instance *c, int logging)
{
    c->logging = logging;
}

void codegen_fmi_setup(codegen_fmi_instance *c, int tolerance_defined, double tolerance,
                       double start)
{
    c->time = start;
    c->rtol = tolerance_defined ? tolerance : 0.0;
    c->phase = INITIALISATION;
}

int codegen_fmi_exit_initialisation(codegen_fmi_instance *c)
{
    const int status = c->model->check(applied(c));
    if (status != 0) {
        c->phase = FAILED;
        return failed(c, status, "the parameters");
    }
    c->phase = RUNNING;
    c->running = 0;
    return CODEGEN_FMI_OK;
}

void codegen_fmi_terminate(codegen_fmi_instance *c)
{
    c->phase = TERMINATED;
}

void codegen_fmi_reset(codegen_fmi_instance *c)
{
    memcpy(c->params, c->model->defaults, (size_t)c->model->n_params * sizeof(double));
    memset(c->inputs, 0, (size_t)c->model->n_loads * sizeof(double));
    memcpy(c->x, c->model->initial, N_STATES(c->model) * sizeof(double));
    c->time = 0.0;
    c->phase = INSTANTIATED;
    c->running = 0;
}

/* theta_dd (c->theta_dd) at the current state, or an error with the reason. */
static int acceleration(codegen_fmi_instance *c)
{
    const int n = c->model->n_dof;
    const int status = c->model->acceleration(applied(c), c->x, c->x + n, c->theta_dd);
    return status == 0 ? CODEGEN_FMI_OK : failed(c, status, "the acceleration at this state");
}

int codegen_fmi_get(codegen_fmi_instance *c, const unsigned *vr, size_t n, double *values)
{
    const codegen_fmi_model *m = c->model;
    const unsigned states = VR_STATES(m), dof = (unsigned)m->n_dof;
    int outputs_ready = 0, accelerations_ready = 0;
    size_t i;
    for (i = 0; i < n; ++i) {
        const unsigned r = vr[i];
        if (r < states) {
            values[i] = c->params[r];
        } else if (r < states + N_STATES(m)) {
            values[i] = c->x[r - states];
        } else if (r < states + N_STATES(m) + dof) {   /* der(theta_k) = theta_d_k */
            values[i] = c->x[r - states - N_STATES(m) + dof];
        } else if (r < VR_INPUTS(m)) {                  /* der(theta_d_k) */
            if (!accelerations_ready && acceleration(c) != CODEGEN_FMI_OK) {
                return CODEGEN_FMI_ERROR;
            }
            accelerations_ready = 1;
            values[i] = c->theta_dd[r - states - N_STATES(m) - dof];
        } else if (r < VR_OUTPUTS(m)) {
            values[i] = c->inputs[r - VR_INPUTS(m)];
        } else if (r < VR_TIME(m)) {
            if (!outputs_ready) {
                const int status = m->outputs(applied(c), c->x, c->x + m->n_dof, c->outputs);
                if (status != 0) {
                    return failed(c, status, "the outputs at this state");
                }
                outputs_ready = 1;
            }
            values[i] = c->outputs[r - VR_OUTPUTS(m)];
        } else if (r == VR_TIME(m)) {
            values[i] = c->time;
        } else {
            return codegen_fmi_fail(c, "get: no variable has value reference %u", r);
        }
    }
    return CODEGEN_FMI_OK;
}

/* Whether a state's new value is a number the motion can start from (else an error in the
 * log): a NaN or an infinity would only come back as NaN, later and from elsewhere. */
static int finite_state(codegen_fmi_instance *c, const char *what, size_t k, double value)
{
    if (isfinite(value)) {
        return 1;
    }
    codegen_fmi_fail(c, "%s: state %lu is %g, not a finite number", what, (unsigned long)k,
                     value);
    return 0;
}

/* Whether value differs from *variable, bit for bit. Setting a variable to the value it has
 * (a host applying a constant input at every step, or putting back the states it got) keeps
 * the integration in progress, which is at that state already. */
static int changes(const double *variable, double value)
{
    return memcmp(variable, &value, sizeof value) != 0;
}

int codegen_fmi_set(codegen_fmi_instance *c, const unsigned *vr, size_t n, const double *values)
{
    const codegen_fmi_model *m = c->model;
    size_t i;
    for (i = 0; i < n; ++i) {   /* every state checked before anything is set */
        const unsigned r = vr[i];
        if (r >= VR_STATES(m) && r < VR_STATES(m) + N_STATES(m)
            && !finite_state(c, "set", r - VR_STATES(m), values[i])) {
            return CODEGEN_FMI_ERROR;
        }
    }
    for (i = 0; i < n; ++i) {
        const unsigned r = vr[i];
        double *variable;
        if (r < VR_STATES(m)) {
            variable = &c->params[r];
        } else if (r < VR_STATES(m) + N_STATES(m)) {
            variable = &c->x[r - VR_STATES(m)];
        } else if (r >= VR_INPUTS(m) && r < VR_OUTPUTS(m)) {
            variable = &c->inputs[r - VR_INPUTS(m)];
        } else {
            return codegen_fmi_fail(c, "set: value reference %u cannot be set", r);
        }
        if (changes(variable, values[i])) {
            c->running = 0;   /* co-simulation restarts from here with what was set */
        }
        *variable = values[i];
    }
    if (c->phase == RUNNING) {
        const int status = m->check(applied(c));
        if (status != 0) {
            return failed(c, status, "the parameters");
        }
    }
    return CODEGEN_FMI_OK;
}

size_t codegen_fmi_states(const codegen_fmi_instance *c)
{
    return N_STATES(c->model);
}

void codegen_fmi_set_time(codegen_fmi_instance *c, double time)
{
    c->time = time;
}

double codegen_fmi_time(const codegen_fmi_instance *c)
{
    return c->time;
}

/* Whether n is the number of states (else an error in the log). */
static int all_states(codegen_fmi_instance *c, size_t n, const char *what)
{
    if (n == N_STATES(c->model)) {
        return 1;
    }
    codegen_fmi_fail(c, "%s: %u states, not %lu", what, N_STATES(c->model), (unsigned long)n);
    return 0;
}

int codegen_fmi_set_states(codegen_fmi_instance *c, const double *x, size_t n)
{
    size_t k;
    if (!all_states(c, n, "setting the states")) {
        return CODEGEN_FMI_ERROR;
    }
    for (k = 0; k < n; ++k) {
        if (!finite_state(c, "setting the states", k, x[k])) {
            return CODEGEN_FMI_ERROR;
        }
    }
    if (memcmp(c->x, x, n * sizeof(double)) != 0) {
        memcpy(c->x, x, n * sizeof(double));
        c->running = 0;
    }
    return CODEGEN_FMI_OK;
}

int codegen_fmi_get_states(codegen_fmi_instance *c, double *x, size_t n)
{
    if (!all_states(c, n, "getting the states")) {
        return CODEGEN_FMI_ERROR;
    }
    memcpy(x, c->x, n * sizeof(double));
    return CODEGEN_FMI_OK;
}

int codegen_fmi_derivatives(codegen_fmi_instance *c, double *dx, size_t n)
{
    const size_t dof = (size_t)c->model->n_dof;
    if (!all_states(c, n, "the derivatives") || acceleration(c) != CODEGEN_FMI_OK) {
        return CODEGEN_FMI_ERROR;
    }
    memcpy(dx, c->x + dof, dof * sizeof(double));
    memcpy(dx + dof, c->theta_dd, dof * sizeof(double));
    return CODEGEN_FMI_OK;
}

/* Whether a step from now continues the integration where the last one ended, c->time: to
 * within the rounding of a host's sums of times (a few units in the last place); from any
 * other time the integration restarts there. */
static int continues(const codegen_fmi_instance *c, double now)
{
    return fabs(now - c->time) <= 8.0 * DBL_EPSILON * fmax(fabs(now), fabs(c->time));
}

int codegen_fmi_step(codegen_fmi_instance *c, double now, double step)
{
    const codegen_fmi_model *m = c->model;
    int status;
    if (c->phase != RUNNING) {
        return codegen_fmi_fail(c, "step: not initialised, or failed before");
    }
    if (!c->running || !continues(c, now)) {
        status = m->start(c->simulation, applied(c), now, c->x, c->x + m->n_dof, c->rtol);
        if (status != 0) {
            return failed(c, status, "the start of the step");
        }
        c->running = 1;
    }
    status = m->advance(c->simulation, now + step, c->x, c->x + m->n_dof);
    if (status != 0) {
        c->running = 0;
        return failed(c, status, "the step");
    }
    c->time = now + step;
    return CODEGEN_FMI_OK;
}
