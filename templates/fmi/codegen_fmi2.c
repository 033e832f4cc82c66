/*
 * codegen_fmi2.c -- the FMI 2.0 interface (Model Exchange and Co-Simulation in one unit) of
 * any mechanism's library, through the descriptor of codegen_fmi2.h. Written once; each FMU
 * adds its generated descriptor (NAME_fmi2.c) and the library.
 *
 * Model Exchange: the host integrates the states (theta, theta_d); fmi2GetDerivatives gives
 * (theta_d, theta_dd) from the library's reduced equation of motion. Co-Simulation:
 * fmi2DoStep integrates with the library's own adaptive Dormand-Prince 5(4) (its
 * NAME_simulation), at the experiment's tolerance; a change of a parameter or an input
 * restarts it from the current state. A state where the motion is not defined (a spring of
 * zero length, a lost assembly) or a parameter the library refuses gives fmi2Error with the
 * library's one-line reason in the log, never a NaN. Memory: allocated at instantiation
 * through the host's callbacks, freed by fmi2FreeInstance; nothing after.
 */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "fmi2Functions.h"
#include "codegen_fmi2.h"

typedef enum { INSTANTIATED, INITIALISATION, RUNNING, TERMINATED, FAILED } phase;

typedef struct instance {
    const codegen_fmi2_model *model;
    fmi2CallbackFunctions callbacks;
    char name[64];
    fmi2Type type;
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
} instance;

#define VR_STATES(m) ((fmi2ValueReference)(m)->n_params)
#define N_STATES(m) (2u * (fmi2ValueReference)(m)->n_dof)
#define VR_INPUTS(m) (VR_STATES(m) + 2u * N_STATES(m))
#define VR_OUTPUTS(m) (VR_INPUTS(m) + (fmi2ValueReference)(m)->n_loads)
#define VR_END(m) (VR_OUTPUTS(m) + (fmi2ValueReference)(m)->n_outputs)

static void say(const instance *c, fmi2Status status, const char *category, const char *format, ...)
{
    char text[256];
    va_list args;
    if (c->callbacks.logger == NULL || (status == fmi2OK && !c->logging)) {
        return;
    }
    va_start(args, format);
    vsnprintf(text, sizeof text, format, args);
    va_end(args);
    c->callbacks.logger(c->callbacks.componentEnvironment, c->name, status, category, "%s", text);
}

/* fmi2Error with the library's reason for status (what failed: ``what``). */
static fmi2Status failed(instance *c, int status, const char *what)
{
    say(c, fmi2Error, "logStatusError", "%s: %s (status %d)", what,
        c->model->status_message(status), status);
    return fmi2Error;
}

static const double *applied(instance *c)
{
    int i;
    memcpy(c->applied, c->params, (size_t)c->model->n_params * sizeof(double));
    for (i = 0; i < c->model->n_loads; ++i) {
        c->applied[c->model->loads[i]] += c->inputs[i];
    }
    return c->applied;
}

static void *allocate(const instance *c, size_t count, size_t size)
{
    return count == 0 ? NULL : c->callbacks.allocateMemory(count, size);
}

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component component, fmi2Boolean on, size_t n, const fmi2String categories[])
{
    (void)n;
    (void)categories;
    ((instance *)component)->logging = on != fmi2False;
    return fmi2OK;
}

void fmi2FreeInstance(fmi2Component component)
{
    instance *c = (instance *)component;
    fmi2CallbackFreeMemory release;
    if (c == NULL) {
        return;
    }
    release = c->callbacks.freeMemory;
    release(c->params);
    release(c->inputs);
    release(c->applied);
    release(c->outputs);
    release(c->x);
    release(c->theta_dd);
    release(c->simulation);
    release(c);
}

fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid, fmi2String resources,
                              const fmi2CallbackFunctions *callbacks, fmi2Boolean visible, fmi2Boolean logging)
{
    const codegen_fmi2_model *m = &codegen_fmi2_the_model;
    instance *c;
    (void)resources;
    (void)visible;
    if (callbacks == NULL || callbacks->allocateMemory == NULL || callbacks->freeMemory == NULL) {
        return NULL;
    }
    c = (instance *)callbacks->allocateMemory(1, sizeof(instance));
    if (c == NULL) {
        return NULL;
    }
    c->model = m;
    c->callbacks = *callbacks;
    snprintf(c->name, sizeof c->name, "%s", name != NULL ? name : "");
    c->type = type;
    c->logging = logging != fmi2False;
    if (guid == NULL || strcmp(guid, m->guid) != 0) {
        say(c, fmi2Error, "logStatusError", "fmi2Instantiate: GUID %s is not this FMU's (%s)",
            guid != NULL ? guid : "(none)", m->guid);
        callbacks->freeMemory(c);
        return NULL;
    }
    c->params = (double *)allocate(c, (size_t)m->n_params, sizeof(double));
    c->applied = (double *)allocate(c, (size_t)m->n_params, sizeof(double));
    c->inputs = (double *)allocate(c, (size_t)m->n_loads, sizeof(double));
    c->outputs = (double *)allocate(c, (size_t)m->n_outputs, sizeof(double));
    c->x = (double *)allocate(c, N_STATES(m), sizeof(double));
    c->theta_dd = (double *)allocate(c, (size_t)m->n_dof, sizeof(double));
    c->simulation = type == fmi2CoSimulation ? allocate(c, 1, m->simulation_size) : NULL;
    if (c->params == NULL || c->applied == NULL || (m->n_loads > 0 && c->inputs == NULL)
        || (m->n_outputs > 0 && c->outputs == NULL) || c->x == NULL || c->theta_dd == NULL
        || (type == fmi2CoSimulation && c->simulation == NULL)) {
        say(c, fmi2Error, "logStatusError", "fmi2Instantiate: out of memory");
        fmi2FreeInstance(c);
        return NULL;
    }
    memcpy(c->params, m->defaults, (size_t)m->n_params * sizeof(double));
    return c;
}

fmi2Status fmi2SetupExperiment(fmi2Component component, fmi2Boolean tolerance_defined, fmi2Real tolerance,
                               fmi2Real start, fmi2Boolean stop_defined, fmi2Real stop)
{
    instance *c = (instance *)component;
    (void)stop_defined;
    (void)stop;
    c->time = start;
    c->rtol = tolerance_defined ? tolerance : 0.0;
    return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component component)
{
    ((instance *)component)->phase = INITIALISATION;
    return fmi2OK;
}

fmi2Status fmi2ExitInitializationMode(fmi2Component component)
{
    instance *c = (instance *)component;
    const int status = c->model->check(applied(c));
    if (status != 0) {
        c->phase = FAILED;
        return failed(c, status, "the parameters");
    }
    c->phase = RUNNING;
    c->running = 0;
    return fmi2OK;
}

fmi2Status fmi2Terminate(fmi2Component component)
{
    ((instance *)component)->phase = TERMINATED;
    return fmi2OK;
}

fmi2Status fmi2Reset(fmi2Component component)
{
    instance *c = (instance *)component;
    memcpy(c->params, c->model->defaults, (size_t)c->model->n_params * sizeof(double));
    memset(c->inputs, 0, (size_t)c->model->n_loads * sizeof(double));
    memset(c->x, 0, N_STATES(c->model) * sizeof(double));
    c->time = 0.0;
    c->phase = INSTANTIATED;
    c->running = 0;
    return fmi2OK;
}

/* theta_dd (c->theta_dd) at the current state, or fmi2Error with the reason. */
static fmi2Status acceleration(instance *c)
{
    const int n = c->model->n_dof;
    const int status = c->model->acceleration(applied(c), c->x, c->x + n, c->theta_dd);
    return status == 0 ? fmi2OK : failed(c, status, "the acceleration at this state");
}

fmi2Status fmi2GetReal(fmi2Component component, const fmi2ValueReference vr[], size_t n, fmi2Real value[])
{
    instance *c = (instance *)component;
    const codegen_fmi2_model *m = c->model;
    const fmi2ValueReference states = VR_STATES(m), dof = (fmi2ValueReference)m->n_dof;
    int outputs_ready = 0, accelerations_ready = 0;
    size_t i;
    for (i = 0; i < n; ++i) {
        const fmi2ValueReference r = vr[i];
        if (r < states) {
            value[i] = c->params[r];
        } else if (r < states + N_STATES(m)) {
            value[i] = c->x[r - states];
        } else if (r < states + N_STATES(m) + dof) {   /* der(theta_k) = theta_d_k */
            value[i] = c->x[r - states - N_STATES(m) + dof];
        } else if (r < VR_INPUTS(m)) {                  /* der(theta_d_k) */
            if (!accelerations_ready && acceleration(c) != fmi2OK) {
                return fmi2Error;
            }
            accelerations_ready = 1;
            value[i] = c->theta_dd[r - states - N_STATES(m) - dof];
        } else if (r < VR_OUTPUTS(m)) {
            value[i] = c->inputs[r - VR_INPUTS(m)];
        } else if (r < VR_END(m)) {
            if (!outputs_ready) {
                const int status = m->outputs(applied(c), c->x, c->x + m->n_dof, c->outputs);
                if (status != 0) {
                    return failed(c, status, "the outputs at this state");
                }
                outputs_ready = 1;
            }
            value[i] = c->outputs[r - VR_OUTPUTS(m)];
        } else {
            say(c, fmi2Error, "logStatusError", "fmi2GetReal: no variable has value reference %u", r);
            return fmi2Error;
        }
    }
    return fmi2OK;
}

fmi2Status fmi2SetReal(fmi2Component component, const fmi2ValueReference vr[], size_t n, const fmi2Real value[])
{
    instance *c = (instance *)component;
    const codegen_fmi2_model *m = c->model;
    size_t i;
    for (i = 0; i < n; ++i) {
        const fmi2ValueReference r = vr[i];
        if (r < VR_STATES(m)) {
            c->params[r] = value[i];
        } else if (r < VR_STATES(m) + N_STATES(m)) {
            c->x[r - VR_STATES(m)] = value[i];
        } else if (r >= VR_INPUTS(m) && r < VR_OUTPUTS(m)) {
            c->inputs[r - VR_INPUTS(m)] = value[i];
        } else {
            say(c, fmi2Error, "logStatusError", "fmi2SetReal: value reference %u cannot be set", r);
            return fmi2Error;
        }
    }
    c->running = 0;   /* co-simulation restarts from here with what was set */
    if (c->phase == RUNNING) {
        const int status = m->check(applied(c));
        if (status != 0) {
            return failed(c, status, "the parameters");
        }
    }
    return fmi2OK;
}

static fmi2Status none_of_type(fmi2Component component, size_t n, const char *what)
{
    if (n == 0) {
        return fmi2OK;
    }
    say((instance *)component, fmi2Error, "logStatusError", "%s: the FMU has no such variable", what);
    return fmi2Error;
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Integer v[])
{
    (void)vr;
    (void)v;
    return none_of_type(c, n, "fmi2GetInteger");
}
fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Boolean v[])
{
    (void)vr;
    (void)v;
    return none_of_type(c, n, "fmi2GetBoolean");
}
fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2String v[])
{
    (void)vr;
    (void)v;
    return none_of_type(c, n, "fmi2GetString");
}
fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Integer v[])
{
    (void)vr;
    (void)v;
    return none_of_type(c, n, "fmi2SetInteger");
}
fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Boolean v[])
{
    (void)vr;
    (void)v;
    return none_of_type(c, n, "fmi2SetBoolean");
}
fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2String v[])
{
    (void)vr;
    (void)v;
    return none_of_type(c, n, "fmi2SetString");
}

/* What the modelDescription.xml declares unsupported. */
static fmi2Status unsupported(fmi2Component component, const char *what)
{
    say((instance *)component, fmi2Error, "logStatusError", "%s is not supported by this FMU", what);
    return fmi2Error;
}

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *s)
{
    (void)s;
    return unsupported(c, "fmi2GetFMUstate");
}
fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate s)
{
    (void)s;
    return unsupported(c, "fmi2SetFMUstate");
}
fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *s)
{
    (void)s;
    return unsupported(c, "fmi2FreeFMUstate");
}
fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate s, size_t *size)
{
    (void)s;
    (void)size;
    return unsupported(c, "fmi2SerializedFMUstateSize");
}
fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate s, fmi2Byte bytes[], size_t size)
{
    (void)s;
    (void)bytes;
    (void)size;
    return unsupported(c, "fmi2SerializeFMUstate");
}
fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte bytes[], size_t size, fmi2FMUstate *s)
{
    (void)bytes;
    (void)size;
    (void)s;
    return unsupported(c, "fmi2DeSerializeFMUstate");
}
fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference u[], size_t nu,
                                        const fmi2ValueReference k[], size_t nk, const fmi2Real dk[], fmi2Real du[])
{
    (void)u;
    (void)nu;
    (void)k;
    (void)nk;
    (void)dk;
    (void)du;
    return unsupported(c, "fmi2GetDirectionalDerivative");
}

/* ------------------------------------------------------------------ Model Exchange */

fmi2Status fmi2EnterEventMode(fmi2Component c)
{
    (void)c;
    return fmi2OK;
}

fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *info)
{
    (void)c;
    info->newDiscreteStatesNeeded = fmi2False;
    info->terminateSimulation = fmi2False;
    info->nominalsOfContinuousStatesChanged = fmi2False;
    info->valuesOfContinuousStatesChanged = fmi2False;
    info->nextEventTimeDefined = fmi2False;
    info->nextEventTime = 0.0;
    return fmi2OK;
}

fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c)
{
    (void)c;
    return fmi2OK;
}

fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean no_set_state, fmi2Boolean *enter_event_mode,
                                       fmi2Boolean *terminate)
{
    (void)c;
    (void)no_set_state;
    *enter_event_mode = fmi2False;
    *terminate = fmi2False;
    return fmi2OK;
}

fmi2Status fmi2SetTime(fmi2Component component, fmi2Real time)
{
    ((instance *)component)->time = time;
    return fmi2OK;
}

/* Whether n is the number of states (else an error in the log). */
static int all_states(instance *c, size_t n, const char *what)
{
    if (n == N_STATES(c->model)) {
        return 1;
    }
    say(c, fmi2Error, "logStatusError", "%s: %u states, not %lu", what, N_STATES(c->model),
        (unsigned long)n);
    return 0;
}

fmi2Status fmi2SetContinuousStates(fmi2Component component, const fmi2Real x[], size_t n)
{
    instance *c = (instance *)component;
    if (!all_states(c, n, "fmi2SetContinuousStates")) {
        return fmi2Error;
    }
    memcpy(c->x, x, n * sizeof(double));
    return fmi2OK;
}

fmi2Status fmi2GetContinuousStates(fmi2Component component, fmi2Real x[], size_t n)
{
    instance *c = (instance *)component;
    if (!all_states(c, n, "fmi2GetContinuousStates")) {
        return fmi2Error;
    }
    memcpy(x, c->x, n * sizeof(double));
    return fmi2OK;
}

fmi2Status fmi2GetDerivatives(fmi2Component component, fmi2Real derivatives[], size_t n)
{
    instance *c = (instance *)component;
    const size_t dof = (size_t)c->model->n_dof;
    if (!all_states(c, n, "fmi2GetDerivatives") || acceleration(c) != fmi2OK) {
        return fmi2Error;
    }
    memcpy(derivatives, c->x + dof, dof * sizeof(double));
    memcpy(derivatives + dof, c->theta_dd, dof * sizeof(double));
    return fmi2OK;
}

fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real indicators[], size_t n)
{
    (void)indicators;
    return none_of_type(c, n, "fmi2GetEventIndicators");
}

fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real nominal[], size_t n)
{
    size_t i;
    (void)c;
    for (i = 0; i < n; ++i) {
        nominal[i] = 1.0;
    }
    return fmi2OK;
}

/* ------------------------------------------------------------------ Co-Simulation */

fmi2Status fmi2DoStep(fmi2Component component, fmi2Real now, fmi2Real step, fmi2Boolean no_set_state)
{
    instance *c = (instance *)component;
    const codegen_fmi2_model *m = c->model;
    int status;
    (void)no_set_state;
    if (c->phase != RUNNING) {
        say(c, fmi2Error, "logStatusError", "fmi2DoStep: not initialised, or failed before");
        return fmi2Error;
    }
    if (!c->running || now != c->time) {
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
    return fmi2OK;
}

fmi2Status fmi2CancelStep(fmi2Component c)
{
    return unsupported(c, "fmi2CancelStep");
}

fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                       const fmi2Integer order[], const fmi2Real value[])
{
    (void)vr;
    (void)order;
    (void)value;
    return n == 0 ? fmi2OK : unsupported(c, "fmi2SetRealInputDerivatives");
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                        const fmi2Integer order[], fmi2Real value[])
{
    (void)vr;
    (void)order;
    (void)value;
    return n == 0 ? fmi2OK : unsupported(c, "fmi2GetRealOutputDerivatives");
}

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind kind, fmi2Status *value)
{
    (void)kind;
    (void)value;
    return unsupported(c, "fmi2GetStatus");
}
fmi2Status fmi2GetRealStatus(fmi2Component component, const fmi2StatusKind kind, fmi2Real *value)
{
    instance *c = (instance *)component;
    if (kind == fmi2LastSuccessfulTime) {
        *value = c->time;
        return fmi2OK;
    }
    return unsupported(c, "fmi2GetRealStatus");
}
fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind kind, fmi2Integer *value)
{
    (void)kind;
    (void)value;
    return unsupported(c, "fmi2GetIntegerStatus");
}
fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind kind, fmi2Boolean *value)
{
    (void)kind;
    (void)value;
    return unsupported(c, "fmi2GetBooleanStatus");
}
fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind kind, fmi2String *value)
{
    (void)kind;
    (void)value;
    return unsupported(c, "fmi2GetStringStatus");
}
