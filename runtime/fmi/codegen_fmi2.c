/*
 * codegen_fmi2.c -- FMI 2.0 (Model Exchange and Co-Simulation in one unit) over one FMU
 * instance of codegen_fmi_core.h. Written once. Memory comes from the host's callbacks.
 */
#include <string.h>

#include "fmi2Functions.h"
#include "codegen_fmi_core.h"

#define C(component) ((codegen_fmi_instance *)(component))
#define STATUS(result) ((result) == CODEGEN_FMI_OK ? fmi2OK : fmi2Error)

/* The host's callbacks, which the core reports through. */
static void report(void *host, const char *instance, int status, const char *category,
                   const char *message)
{
    const fmi2CallbackFunctions *callbacks = (const fmi2CallbackFunctions *)host;
    if (callbacks->logger != NULL) {
        callbacks->logger(callbacks->componentEnvironment, instance, (fmi2Status)status, category,
                          "%s", message);
    }
}

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid, fmi2String resources,
                              const fmi2CallbackFunctions *callbacks, fmi2Boolean visible, fmi2Boolean logging)
{
    codegen_fmi_memory memory;
    fmi2CallbackFunctions *host;
    codegen_fmi_instance *c;
    (void)resources;
    (void)visible;
    if (callbacks == NULL || callbacks->allocateMemory == NULL || callbacks->freeMemory == NULL) {
        return NULL;
    }
    host = (fmi2CallbackFunctions *)callbacks->allocateMemory(1, sizeof *host);
    if (host == NULL) {
        return NULL;
    }
    memcpy(host, callbacks, sizeof *host);
    memory.allocate = callbacks->allocateMemory;
    memory.release = callbacks->freeMemory;
    c = codegen_fmi_new(name, guid, type == fmi2CoSimulation, logging != fmi2False, memory, report,
                        host);
    if (c == NULL) {
        callbacks->freeMemory(host);
    }
    return c;
}

void fmi2FreeInstance(fmi2Component component)
{
    if (component != NULL) {
        void *host = codegen_fmi_host(C(component));
        const fmi2CallbackFreeMemory release = ((fmi2CallbackFunctions *)host)->freeMemory;
        codegen_fmi_free(C(component));
        release(host);
    }
}

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean on, size_t n, const fmi2String categories[])
{
    (void)n;
    (void)categories;
    codegen_fmi_set_logging(C(c), on != fmi2False);
    return fmi2OK;
}

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tolerance_defined, fmi2Real tolerance,
                               fmi2Real start, fmi2Boolean stop_defined, fmi2Real stop)
{
    (void)stop_defined;
    (void)stop;
    codegen_fmi_setup(C(c), tolerance_defined != fmi2False, tolerance, start);
    return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c)
{
    (void)c;
    return fmi2OK;
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c)
{
    return STATUS(codegen_fmi_exit_initialisation(C(c)));
}

fmi2Status fmi2Terminate(fmi2Component c)
{
    codegen_fmi_terminate(C(c));
    return fmi2OK;
}

fmi2Status fmi2Reset(fmi2Component c)
{
    codegen_fmi_reset(C(c));
    return fmi2OK;
}

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real value[])
{
    return STATUS(codegen_fmi_get(C(c), vr, n, value));
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Real value[])
{
    return STATUS(codegen_fmi_set(C(c), vr, n, value));
}

/* No variable of another type: nothing to get or set. */
static fmi2Status none_of_type(fmi2Component c, size_t n, const char *what)
{
    return n == 0 ? fmi2OK : STATUS(codegen_fmi_fail(C(c), "%s: the FMU has no such variable", what));
}

#define NONE_OF_TYPE(name, type, qualifier)                                                        \
    fmi2Status name(fmi2Component c, const fmi2ValueReference vr[], size_t n, qualifier type v[]) \
    {                                                                                              \
        (void)vr;                                                                                  \
        (void)v;                                                                                   \
        return none_of_type(c, n, #name);                                                          \
    }
NONE_OF_TYPE(fmi2GetInteger, fmi2Integer, )
NONE_OF_TYPE(fmi2GetBoolean, fmi2Boolean, )
NONE_OF_TYPE(fmi2GetString, fmi2String, )
NONE_OF_TYPE(fmi2SetInteger, fmi2Integer, const)
NONE_OF_TYPE(fmi2SetBoolean, fmi2Boolean, const)
NONE_OF_TYPE(fmi2SetString, fmi2String, const)

/* What the modelDescription.xml declares unsupported. */
static fmi2Status unsupported(fmi2Component c, const char *what)
{
    return STATUS(codegen_fmi_fail(C(c), "%s is not supported by this FMU", what));
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
    memset(info, 0, sizeof *info);   /* no event, nothing changed */
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

fmi2Status fmi2SetTime(fmi2Component c, fmi2Real time)
{
    codegen_fmi_set_time(C(c), time);
    return fmi2OK;
}

fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t n)
{
    return STATUS(codegen_fmi_set_states(C(c), x, n));
}

fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t n)
{
    return STATUS(codegen_fmi_get_states(C(c), x, n));
}

fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real derivatives[], size_t n)
{
    return STATUS(codegen_fmi_derivatives(C(c), derivatives, n));
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

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real now, fmi2Real step, fmi2Boolean no_set_state)
{
    (void)no_set_state;
    return STATUS(codegen_fmi_step(C(c), now, step));
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
fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind kind, fmi2Real *value)
{
    if (kind == fmi2LastSuccessfulTime) {
        *value = codegen_fmi_time(C(c));
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
