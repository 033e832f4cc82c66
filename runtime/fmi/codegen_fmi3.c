/*
 * codegen_fmi3.c -- FMI 3.0 (Model Exchange and Co-Simulation in one unit) over one FMU
 * instance of codegen_fmi_core.h. Written once. FMI 3.0 gives no memory callbacks: an
 * instance's memory comes from calloc when it is instantiated, and is freed with it.
 */
#include <stdlib.h>

#include "fmi3Functions.h"
#include "codegen_fmi_core.h"

#define C(instance) ((codegen_fmi_instance *)(instance))
#define STATUS(result) ((result) == CODEGEN_FMI_OK ? fmi3OK : fmi3Error)

typedef struct host {
    fmi3InstanceEnvironment environment;
    fmi3LogMessageCallback log;
} host;

static void report(void *h, const char *instance, int status, const char *category,
                   const char *message)
{
    const host *to = (const host *)h;
    (void)instance;
    if (to->log != NULL) {
        to->log(to->environment, (fmi3Status)status, category, message);
    }
}

static fmi3Instance instantiate(fmi3String name, fmi3String token, int cosimulation, fmi3Boolean logging,
                                fmi3InstanceEnvironment environment, fmi3LogMessageCallback log)
{
    const codegen_fmi_memory memory = {calloc, free};
    host *h = (host *)calloc(1, sizeof(host));
    codegen_fmi_instance *c;
    if (h == NULL) {
        return NULL;
    }
    h->environment = environment;
    h->log = log;
    c = codegen_fmi_new(name, token, cosimulation, logging, memory, report, h);
    if (c == NULL) {
        free(h);
    }
    return c;
}

const char *fmi3GetVersion(void) { return fmi3Version; }

fmi3Instance fmi3InstantiateModelExchange(fmi3String name, fmi3String token, fmi3String resources,
                                          fmi3Boolean visible, fmi3Boolean logging,
                                          fmi3InstanceEnvironment environment, fmi3LogMessageCallback log)
{
    (void)resources;
    (void)visible;
    return instantiate(name, token, 0, logging, environment, log);
}

fmi3Instance fmi3InstantiateCoSimulation(fmi3String name, fmi3String token, fmi3String resources,
                                         fmi3Boolean visible, fmi3Boolean logging, fmi3Boolean event_mode,
                                         fmi3Boolean early_return, const fmi3ValueReference required[],
                                         size_t n_required, fmi3InstanceEnvironment environment,
                                         fmi3LogMessageCallback log, fmi3IntermediateUpdateCallback update)
{
    (void)resources;
    (void)visible;
    (void)event_mode;
    (void)early_return;
    (void)required;
    (void)n_required;
    (void)update;
    return instantiate(name, token, 1, logging, environment, log);
}

fmi3Instance fmi3InstantiateScheduledExecution(fmi3String name, fmi3String token, fmi3String resources,
                                               fmi3Boolean visible, fmi3Boolean logging,
                                               fmi3InstanceEnvironment environment, fmi3LogMessageCallback log,
                                               fmi3ClockUpdateCallback clock, fmi3LockPreemptionCallback lock,
                                               fmi3UnlockPreemptionCallback unlock)
{
    (void)name;
    (void)token;
    (void)resources;
    (void)visible;
    (void)logging;
    (void)environment;
    (void)log;
    (void)clock;
    (void)lock;
    (void)unlock;
    return NULL;   /* not an interface type of this FMU */
}

void fmi3FreeInstance(fmi3Instance instance)
{
    if (instance != NULL) {
        void *h = codegen_fmi_host(C(instance));
        codegen_fmi_free(C(instance));
        free(h);
    }
}

fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean on, size_t n, const fmi3String categories[])
{
    (void)n;
    (void)categories;
    codegen_fmi_set_logging(C(instance), on);
    return fmi3OK;
}

fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean tolerance_defined, fmi3Float64 tolerance,
                                       fmi3Float64 start, fmi3Boolean stop_defined, fmi3Float64 stop)
{
    (void)stop_defined;
    (void)stop;
    codegen_fmi_setup(C(instance), tolerance_defined, tolerance, start);
    return fmi3OK;
}

fmi3Status fmi3ExitInitializationMode(fmi3Instance instance)
{
    return STATUS(codegen_fmi_exit_initialisation(C(instance)));
}

fmi3Status fmi3EnterEventMode(fmi3Instance instance)
{
    (void)instance;
    return fmi3OK;
}

fmi3Status fmi3Terminate(fmi3Instance instance)
{
    codegen_fmi_terminate(C(instance));
    return fmi3OK;
}

fmi3Status fmi3Reset(fmi3Instance instance)
{
    codegen_fmi_reset(C(instance));
    return fmi3OK;
}

fmi3Status fmi3GetFloat64(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, fmi3Float64 values[],
                          size_t n_values)
{
    if (n_values != n) {
        return STATUS(codegen_fmi_fail(C(instance), "fmi3GetFloat64: scalars only (%lu values for %lu)",
                                       (unsigned long)n_values, (unsigned long)n));
    }
    return STATUS(codegen_fmi_get(C(instance), vr, n, values));
}

fmi3Status fmi3SetFloat64(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                          const fmi3Float64 values[], size_t n_values)
{
    if (n_values != n) {
        return STATUS(codegen_fmi_fail(C(instance), "fmi3SetFloat64: scalars only (%lu values for %lu)",
                                       (unsigned long)n_values, (unsigned long)n));
    }
    return STATUS(codegen_fmi_set(C(instance), vr, n, values));
}

/* No variable of another type: nothing to get or set. */
static fmi3Status none_of_type(fmi3Instance instance, size_t n, const char *what)
{
    return n == 0 ? fmi3OK : STATUS(codegen_fmi_fail(C(instance), "%s: the FMU has no such variable", what));
}

#define NONE_OF_TYPE(name, type, qualifier)                                                          \
    fmi3Status name(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, qualifier type v[], \
                    size_t n_values)                                                                \
    {                                                                                                \
        (void)vr;                                                                                    \
        (void)v;                                                                                     \
        (void)n_values;                                                                              \
        return none_of_type(instance, n, #name);                                                     \
    }
NONE_OF_TYPE(fmi3GetFloat32, fmi3Float32, )
NONE_OF_TYPE(fmi3GetInt8, fmi3Int8, )
NONE_OF_TYPE(fmi3GetUInt8, fmi3UInt8, )
NONE_OF_TYPE(fmi3GetInt16, fmi3Int16, )
NONE_OF_TYPE(fmi3GetUInt16, fmi3UInt16, )
NONE_OF_TYPE(fmi3GetInt32, fmi3Int32, )
NONE_OF_TYPE(fmi3GetUInt32, fmi3UInt32, )
NONE_OF_TYPE(fmi3GetInt64, fmi3Int64, )
NONE_OF_TYPE(fmi3GetUInt64, fmi3UInt64, )
NONE_OF_TYPE(fmi3GetBoolean, fmi3Boolean, )
NONE_OF_TYPE(fmi3GetString, fmi3String, )
NONE_OF_TYPE(fmi3SetFloat32, fmi3Float32, const)
NONE_OF_TYPE(fmi3SetInt8, fmi3Int8, const)
NONE_OF_TYPE(fmi3SetUInt8, fmi3UInt8, const)
NONE_OF_TYPE(fmi3SetInt16, fmi3Int16, const)
NONE_OF_TYPE(fmi3SetUInt16, fmi3UInt16, const)
NONE_OF_TYPE(fmi3SetInt32, fmi3Int32, const)
NONE_OF_TYPE(fmi3SetUInt32, fmi3UInt32, const)
NONE_OF_TYPE(fmi3SetInt64, fmi3Int64, const)
NONE_OF_TYPE(fmi3SetUInt64, fmi3UInt64, const)
NONE_OF_TYPE(fmi3SetBoolean, fmi3Boolean, const)
NONE_OF_TYPE(fmi3SetString, fmi3String, const)

fmi3Status fmi3GetBinary(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, size_t sizes[],
                         fmi3Binary values[], size_t n_values)
{
    (void)vr;
    (void)sizes;
    (void)values;
    (void)n_values;
    return none_of_type(instance, n, "fmi3GetBinary");
}

fmi3Status fmi3SetBinary(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, const size_t sizes[],
                         const fmi3Binary values[], size_t n_values)
{
    (void)vr;
    (void)sizes;
    (void)values;
    (void)n_values;
    return none_of_type(instance, n, "fmi3SetBinary");
}

fmi3Status fmi3GetClock(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, fmi3Clock values[])
{
    (void)vr;
    (void)values;
    return none_of_type(instance, n, "fmi3GetClock");
}

fmi3Status fmi3SetClock(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, const fmi3Clock values[])
{
    (void)vr;
    (void)values;
    return none_of_type(instance, n, "fmi3SetClock");
}

/* What the modelDescription.xml declares unsupported. */
static fmi3Status unsupported(fmi3Instance instance, const char *what)
{
    return STATUS(codegen_fmi_fail(C(instance), "%s is not supported by this FMU", what));
}

fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance instance, fmi3ValueReference vr, size_t *n)
{
    (void)vr;
    (void)n;
    return unsupported(instance, "fmi3GetNumberOfVariableDependencies");
}

fmi3Status fmi3GetVariableDependencies(fmi3Instance instance, fmi3ValueReference dependent, size_t element[],
                                       fmi3ValueReference independents[], size_t elements[],
                                       fmi3DependencyKind kinds[], size_t n)
{
    (void)dependent;
    (void)element;
    (void)independents;
    (void)elements;
    (void)kinds;
    (void)n;
    return unsupported(instance, "fmi3GetVariableDependencies");
}

fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState *state)
{
    (void)state;
    return unsupported(instance, "fmi3GetFMUState");
}
fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState state)
{
    (void)state;
    return unsupported(instance, "fmi3SetFMUState");
}
fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState *state)
{
    (void)state;
    return unsupported(instance, "fmi3FreeFMUState");
}
fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState state, size_t *size)
{
    (void)state;
    (void)size;
    return unsupported(instance, "fmi3SerializedFMUStateSize");
}
fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState state, fmi3Byte bytes[], size_t size)
{
    (void)state;
    (void)bytes;
    (void)size;
    return unsupported(instance, "fmi3SerializeFMUState");
}
fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte bytes[], size_t size, fmi3FMUState *state)
{
    (void)bytes;
    (void)size;
    (void)state;
    return unsupported(instance, "fmi3DeserializeFMUState");
}

#define NO_DERIVATIVE(name)                                                                             \
    fmi3Status name(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t n_unknowns,    \
                    const fmi3ValueReference knowns[], size_t n_knowns, const fmi3Float64 seed[],     \
                    size_t n_seed, fmi3Float64 sensitivity[], size_t n_sensitivity)                    \
    {                                                                                                 \
        (void)unknowns;                                                                               \
        (void)n_unknowns;                                                                             \
        (void)knowns;                                                                                 \
        (void)n_knowns;                                                                               \
        (void)seed;                                                                                   \
        (void)n_seed;                                                                                 \
        (void)sensitivity;                                                                            \
        (void)n_sensitivity;                                                                          \
        return unsupported(instance, #name);                                                          \
    }
NO_DERIVATIVE(fmi3GetDirectionalDerivative)
NO_DERIVATIVE(fmi3GetAdjointDerivative)

fmi3Status fmi3EnterConfigurationMode(fmi3Instance instance)
{
    return unsupported(instance, "fmi3EnterConfigurationMode");
}
fmi3Status fmi3ExitConfigurationMode(fmi3Instance instance)
{
    return unsupported(instance, "fmi3ExitConfigurationMode");
}

/* Clocks: the FMU has none. */
fmi3Status fmi3GetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                                  fmi3Float64 intervals[], fmi3IntervalQualifier qualifiers[])
{
    (void)vr;
    (void)intervals;
    (void)qualifiers;
    return none_of_type(instance, n, "fmi3GetIntervalDecimal");
}
fmi3Status fmi3GetIntervalFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                                   fmi3UInt64 counters[], fmi3UInt64 resolutions[],
                                   fmi3IntervalQualifier qualifiers[])
{
    (void)vr;
    (void)counters;
    (void)resolutions;
    (void)qualifiers;
    return none_of_type(instance, n, "fmi3GetIntervalFraction");
}
fmi3Status fmi3GetShiftDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, fmi3Float64 shifts[])
{
    (void)vr;
    (void)shifts;
    return none_of_type(instance, n, "fmi3GetShiftDecimal");
}
fmi3Status fmi3GetShiftFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                                fmi3UInt64 counters[], fmi3UInt64 resolutions[])
{
    (void)vr;
    (void)counters;
    (void)resolutions;
    return none_of_type(instance, n, "fmi3GetShiftFraction");
}
fmi3Status fmi3SetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                                  const fmi3Float64 intervals[])
{
    (void)vr;
    (void)intervals;
    return none_of_type(instance, n, "fmi3SetIntervalDecimal");
}
fmi3Status fmi3SetIntervalFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                                   const fmi3UInt64 counters[], const fmi3UInt64 resolutions[])
{
    (void)vr;
    (void)counters;
    (void)resolutions;
    return none_of_type(instance, n, "fmi3SetIntervalFraction");
}
fmi3Status fmi3SetShiftDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                               const fmi3Float64 shifts[])
{
    (void)vr;
    (void)shifts;
    return none_of_type(instance, n, "fmi3SetShiftDecimal");
}
fmi3Status fmi3SetShiftFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                                const fmi3UInt64 counters[], const fmi3UInt64 resolutions[])
{
    (void)vr;
    (void)counters;
    (void)resolutions;
    return none_of_type(instance, n, "fmi3SetShiftFraction");
}

fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance instance)
{
    (void)instance;
    return fmi3OK;
}

fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean *update, fmi3Boolean *terminate,
                                    fmi3Boolean *nominals_changed, fmi3Boolean *values_changed,
                                    fmi3Boolean *next_defined, fmi3Float64 *next)
{
    (void)instance;
    *update = *terminate = *nominals_changed = *values_changed = *next_defined = fmi3False;
    *next = 0.0;
    return fmi3OK;
}

/* ------------------------------------------------------------------ Model Exchange */

fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance)
{
    (void)instance;
    return fmi3OK;
}

fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance, fmi3Boolean no_set_state,
                                       fmi3Boolean *enter_event_mode, fmi3Boolean *terminate)
{
    (void)instance;
    (void)no_set_state;
    *enter_event_mode = fmi3False;
    *terminate = fmi3False;
    return fmi3OK;
}

fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time)
{
    codegen_fmi_set_time(C(instance), time);
    return fmi3OK;
}

fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 x[], size_t n)
{
    return STATUS(codegen_fmi_set_states(C(instance), x, n));
}

fmi3Status fmi3GetContinuousStates(fmi3Instance instance, fmi3Float64 x[], size_t n)
{
    return STATUS(codegen_fmi_get_states(C(instance), x, n));
}

fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance instance, fmi3Float64 derivatives[], size_t n)
{
    return STATUS(codegen_fmi_derivatives(C(instance), derivatives, n));
}

fmi3Status fmi3GetEventIndicators(fmi3Instance instance, fmi3Float64 indicators[], size_t n)
{
    (void)indicators;
    return none_of_type(instance, n, "fmi3GetEventIndicators");
}

fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance instance, fmi3Float64 nominals[], size_t n)
{
    size_t i;
    (void)instance;
    for (i = 0; i < n; ++i) {
        nominals[i] = 1.0;
    }
    return fmi3OK;
}

fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t *n)
{
    (void)instance;
    *n = 0;
    return fmi3OK;
}

fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t *n)
{
    *n = codegen_fmi_states(C(instance));
    return fmi3OK;
}

/* ------------------------------------------------------------------ Co-Simulation */

fmi3Status fmi3EnterStepMode(fmi3Instance instance)
{
    (void)instance;
    return fmi3OK;
}

fmi3Status fmi3GetOutputDerivatives(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                                    const fmi3Int32 orders[], fmi3Float64 values[], size_t n_values)
{
    (void)vr;
    (void)orders;
    (void)values;
    (void)n_values;
    return n == 0 ? fmi3OK : unsupported(instance, "fmi3GetOutputDerivatives");
}

fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 now, fmi3Float64 step, fmi3Boolean no_set_state,
                      fmi3Boolean *event_handling_needed, fmi3Boolean *terminate, fmi3Boolean *early_return,
                      fmi3Float64 *last_successful_time)
{
    const int result = codegen_fmi_step(C(instance), now, step);
    (void)no_set_state;
    *event_handling_needed = fmi3False;
    *terminate = fmi3False;
    *early_return = fmi3False;
    *last_successful_time = codegen_fmi_time(C(instance));
    return STATUS(result);
}

fmi3Status fmi3ActivateModelPartition(fmi3Instance instance, fmi3ValueReference clock, fmi3Float64 time)
{
    (void)clock;
    (void)time;
    return unsupported(instance, "fmi3ActivateModelPartition");
}
