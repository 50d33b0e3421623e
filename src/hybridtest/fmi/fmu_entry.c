/* See fmu_entry.h. Every function of the FMI 2.0 header fmi2Functions.h (44) and of the FMI
 * 3.0 header fmi3Functions.h (75), written from the standards' text (FMI 2.0: sections 2.1,
 * 3.2, 4.2; FMI 3.0: sections 2.3, 3.2, 4.2, 5.2) over the model table `fmu_model`.
 * tests/fmi/fmu_entry_points_test.cc checks a built binary against the same lists.
 * The FMI 3 types this file needs beyond fmi3_api.h are the standard's platform types:
 * Float32 float, Int8..UInt64 the <stdint.h> integers, Binary a const uint8_t*, Clock bool. */
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hybridtest/fmi/fmi2_api.h"
#include "hybridtest/fmi/fmi3_api.h"
#include "hybridtest/fmi/fmu_entry.h"

#define EXPORT __attribute__((visibility("default")))

struct FmuHost {
  int version;
  char name[128];
  fmi2CallbackLogger logger2;
  fmi2ComponentEnvironment env2;
  fmi3LogMessageCallback log3;
  fmi3InstanceEnvironment env3;
};

typedef struct {
  FmuHost host;
  void* self;
  double time;
} Instance;

/* An FMU state: the model's bytes. */
typedef struct {
  void* bytes;
  size_t size;
} Blob;

void fmu_log(const FmuHost* host, int status, const char* format, ...) {
  if (host == NULL || (host->logger2 == NULL && host->log3 == NULL)) return;
  char text[1024];
  va_list args;
  va_start(args, format);
  vsnprintf(text, sizeof text, format, args);
  va_end(args);
  const char* category = status >= FMU_ERROR ? "logStatusError" : "logEvents";
  if (host->logger2 != NULL) {
    host->logger2(host->env2, host->name, (fmi2Status)status, category, "%s", text);
  } else {
    host->log3(host->env3, (fmi3Status)status, category, text);
  }
}

int fmu_host_version(const FmuHost* host) { return host->version; }

int fmu_save_record(const void* record, size_t size, void** bytes, size_t* out_size) {
  *bytes = malloc(size);
  if (*bytes == NULL) return FMU_ERROR;
  memcpy(*bytes, record, size);
  *out_size = size;
  return FMU_OK;
}

int fmu_restore_record(const FmuHost* host, void* record, size_t size, const void* bytes,
                       size_t in_size) {
  if (in_size != size) {
    fmu_log(host, FMU_ERROR, "the FMU state has %zu bytes, this FMU's has %zu: it is of "
            "another FMU", in_size, size);
    return FMU_ERROR;
  }
  memcpy(record, bytes, size);
  return FMU_OK;
}

static Instance* New(int version, const char* name) {
  Instance* in = (Instance*)calloc(1, sizeof(Instance));
  if (in == NULL) return NULL;
  in->host.version = version;
  strncpy(in->host.name, name != NULL ? name : "", sizeof in->host.name - 1);
  return in;
}

/* The model's instance behind `in`, or NULL after logging (a failed instantiation). */
static Instance* Make(Instance* in, const char* call, const char* token, const char* resources) {
  if (fmu_model.token != NULL && (token == NULL || strcmp(token, fmu_model.token) != 0)) {
    fmu_log(&in->host, FMU_ERROR, "%s: token '%s' is not this FMU's (%s): the description and "
            "the binary are of different FMUs", call, token != NULL ? token : "", fmu_model.token);
  } else {
    in->self = fmu_model.instantiate(&in->host, token, resources);
    if (in->self != NULL) return in;
  }
  free(in);
  return NULL;
}

static int Unsupported(void* c, const char* call, const char* why) {
  if (c != NULL) fmu_log(&((Instance*)c)->host, FMU_ERROR, "%s is not supported: %s", call, why);
  return FMU_ERROR;
}

static int Wrong(void* c, const char* call, const char* why) {
  if (c != NULL) fmu_log(&((Instance*)c)->host, FMU_ERROR, "%s: %s", call, why);
  return FMU_ERROR;
}

#define SELF(c) (((Instance*)(c))->self)
#define CHECK(c) \
  if ((c) == NULL) return FMU_ERROR

static int Setup(void* c, double start, int stop_defined, double stop) {
  CHECK(c);
  ((Instance*)c)->time = start;
  return fmu_model.setup(SELF(c), start, stop_defined, stop);
}
static int ExitInit(void* c) {
  CHECK(c);
  return fmu_model.exit_initialization != NULL ? fmu_model.exit_initialization(SELF(c)) : FMU_OK;
}
static int Reset(void* c, const char* call) {
  CHECK(c);
  if (fmu_model.reset == NULL) {
    return Unsupported(c, call, "free the instance and instantiate it again");
  }
  return fmu_model.reset(SELF(c));
}
static int Step(void* c, double t, double h) {
  CHECK(c);
  return fmu_model.do_step(SELF(c), t, h, &((Instance*)c)->time);
}

/* The FMU state, shared by both versions. */
static int GetState(void* c, const char* call, void** state) {
  CHECK(c);
  if (fmu_model.save_state == NULL) return Unsupported(c, call, "canGetAndSetFMUState is false");
  if (state == NULL) return Wrong(c, call, "no place for the FMU state given (NULL)");
  Blob* blob = (Blob*)(*state != NULL ? *state : calloc(1, sizeof(Blob)));
  if (blob == NULL) return FMU_ERROR;
  free(blob->bytes);
  blob->bytes = NULL;
  blob->size = 0;
  *state = blob;
  return fmu_model.save_state(SELF(c), &blob->bytes, &blob->size);
}
static int SetState(void* c, const char* call, void* state) {
  CHECK(c);
  if (fmu_model.restore_state == NULL) return Unsupported(c, call, "canGetAndSetFMUState is false");
  if (state == NULL) return Wrong(c, call, "no FMU state given (NULL)");
  return fmu_model.restore_state(SELF(c), ((Blob*)state)->bytes, ((Blob*)state)->size);
}
static int FreeState(void** state) {
  if (state != NULL && *state != NULL) {
    free(((Blob*)*state)->bytes);
    free(*state);
    *state = NULL;
  }
  return FMU_OK;
}
static int StateSize(void* c, const char* call, void* state, size_t* size) {
  if (state == NULL) return Wrong(c, call, "no FMU state given (NULL)");
  *size = ((Blob*)state)->size;
  return FMU_OK;
}
static int Serialize(void* c, const char* call, void* state, void* bytes, size_t size) {
  if (state == NULL) return Wrong(c, call, "no FMU state given (NULL)");
  if (size < ((Blob*)state)->size) return Wrong(c, call, "the buffer is smaller than the state");
  if (((Blob*)state)->size > 0) memcpy(bytes, ((Blob*)state)->bytes, ((Blob*)state)->size);
  return FMU_OK;
}
static int Deserialize(void* c, const char* call, const void* bytes, size_t size, void** state) {
  if (fmu_model.save_state == NULL) return Unsupported(c, call, "canSerializeFMUState is false");
  if (state == NULL) return Wrong(c, call, "no place for the FMU state given (NULL)");
  Blob* blob = (Blob*)(*state != NULL ? *state : calloc(1, sizeof(Blob)));
  if (blob == NULL) return FMU_ERROR;
  void* copy = malloc(size > 0 ? size : 1);
  if (copy == NULL) return FMU_ERROR;
  if (size > 0) memcpy(copy, bytes, size);
  free(blob->bytes);
  blob->bytes = copy;
  blob->size = size;
  *state = blob;
  return FMU_OK;
}

/* ---------------------------------------------------------------- FMI 2.0 (44 functions) */

#define NO_ME2 "this FMU is for co-simulation only (no ModelExchange in its description)"
#define ONLY_REAL "every variable of this FMU is a Real"

EXPORT const char* fmi2GetTypesPlatform(void) { return "default"; }
EXPORT const char* fmi2GetVersion(void) { return "2.0"; }
EXPORT fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean on, size_t n, const fmi2String k[]) {
  (void)on; (void)n; (void)k;
  return c != NULL ? fmi2OK : fmi2Error;
}
EXPORT fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid,
                                     fmi2String resources, const fmi2CallbackFunctions* cb,
                                     fmi2Boolean visible, fmi2Boolean logging) {
  (void)visible; (void)logging;
  Instance* in = New(2, name);
  if (in == NULL) return NULL;
  if (cb != NULL) {
    in->host.logger2 = cb->logger;
    in->host.env2 = cb->componentEnvironment;
  }
  if (type != fmi2CoSimulation) {
    fmu_log(&in->host, FMU_ERROR, "fmi2Instantiate: %s", NO_ME2);
    free(in);
    return NULL;
  }
  return Make(in, "fmi2Instantiate", guid, resources);
}
EXPORT void fmi2FreeInstance(fmi2Component c) {
  if (c == NULL) return;
  fmu_model.free_instance(SELF(c));
  free(c);
}
EXPORT fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tol_defined, fmi2Real tol,
                                      fmi2Real start, fmi2Boolean stop_defined, fmi2Real stop) {
  (void)tol_defined; (void)tol;
  return (fmi2Status)Setup(c, start, stop_defined, stop);
}
EXPORT fmi2Status fmi2EnterInitializationMode(fmi2Component c) { return c != NULL ? fmi2OK : fmi2Error; }
EXPORT fmi2Status fmi2ExitInitializationMode(fmi2Component c) { return (fmi2Status)ExitInit(c); }
EXPORT fmi2Status fmi2Terminate(fmi2Component c) { return c != NULL ? fmi2OK : fmi2Error; }
EXPORT fmi2Status fmi2Reset(fmi2Component c) { return (fmi2Status)Reset(c, "fmi2Reset"); }

EXPORT fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real v[]) {
  if (c == NULL) return fmi2Error;
  return (fmi2Status)fmu_model.get(SELF(c), vr, n, v);
}
EXPORT fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Real v[]) {
  if (c == NULL) return fmi2Error;
  return (fmi2Status)fmu_model.set(SELF(c), vr, n, v);
}
#define NONE2(call, type)                                                                     \
  EXPORT fmi2Status call(fmi2Component c, const fmi2ValueReference vr[], size_t n, type v[]) { \
    (void)vr; (void)v;                                                                        \
    return n == 0 ? fmi2OK : (fmi2Status)Unsupported(c, #call, ONLY_REAL);                   \
  }
NONE2(fmi2GetInteger, fmi2Integer)
NONE2(fmi2GetBoolean, fmi2Boolean)
NONE2(fmi2GetString, fmi2String)
NONE2(fmi2SetInteger, const fmi2Integer)
NONE2(fmi2SetBoolean, const fmi2Boolean)
NONE2(fmi2SetString, const fmi2String)

EXPORT fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate* s) { return (fmi2Status)GetState(c, "fmi2GetFMUstate", s); }
EXPORT fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate s) { return (fmi2Status)SetState(c, "fmi2SetFMUstate", s); }
EXPORT fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate* s) { (void)c; return (fmi2Status)FreeState(s); }
EXPORT fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate s, size_t* size) {
  return (fmi2Status)StateSize(c, "fmi2SerializedFMUstateSize", s, size);
}
EXPORT fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate s, fmi2Byte b[], size_t size) {
  return (fmi2Status)Serialize(c, "fmi2SerializeFMUstate", s, b, size);
}
EXPORT fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte b[], size_t size, fmi2FMUstate* s) {
  return (fmi2Status)Deserialize(c, "fmi2DeSerializeFMUstate", b, size, s);
}
EXPORT fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference u[], size_t nu,
                                               const fmi2ValueReference k[], size_t nk,
                                               const fmi2Real dk[], fmi2Real du[]) {
  (void)u; (void)nu; (void)k; (void)nk; (void)dk; (void)du;
  return (fmi2Status)Unsupported(c, "fmi2GetDirectionalDerivative", "providesDirectionalDerivative is false");
}

/* Model exchange (FMI 2.0 section 3.2): not declared by these FMUs. */
EXPORT fmi2Status fmi2EnterEventMode(fmi2Component c) { return (fmi2Status)Unsupported(c, "fmi2EnterEventMode", NO_ME2); }
EXPORT fmi2Status fmi2NewDiscreteStates(fmi2Component c, void* event_info) {
  (void)event_info;
  return (fmi2Status)Unsupported(c, "fmi2NewDiscreteStates", NO_ME2);
}
EXPORT fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c) { return (fmi2Status)Unsupported(c, "fmi2EnterContinuousTimeMode", NO_ME2); }
EXPORT fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean no_set, fmi2Boolean* enter_event,
                                              fmi2Boolean* terminate) {
  (void)no_set; (void)enter_event; (void)terminate;
  return (fmi2Status)Unsupported(c, "fmi2CompletedIntegratorStep", NO_ME2);
}
EXPORT fmi2Status fmi2SetTime(fmi2Component c, fmi2Real t) { (void)t; return (fmi2Status)Unsupported(c, "fmi2SetTime", NO_ME2); }
#define ME2(call, qualifier)                                                \
  EXPORT fmi2Status call(fmi2Component c, qualifier fmi2Real x[], size_t n) { \
    (void)x; (void)n;                                                       \
    return (fmi2Status)Unsupported(c, #call, NO_ME2);                       \
  }
ME2(fmi2SetContinuousStates, const)
ME2(fmi2GetDerivatives, )
ME2(fmi2GetEventIndicators, )
ME2(fmi2GetContinuousStates, )
ME2(fmi2GetNominalsOfContinuousStates, )

/* Co-simulation (FMI 2.0 section 4.2). */
EXPORT fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                              const fmi2Integer order[], const fmi2Real v[]) {
  (void)vr; (void)n; (void)order; (void)v;
  return (fmi2Status)Unsupported(c, "fmi2SetRealInputDerivatives", "canInterpolateInputs is false");
}
EXPORT fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                               const fmi2Integer order[], fmi2Real v[]) {
  (void)vr; (void)n; (void)order; (void)v;
  return (fmi2Status)Unsupported(c, "fmi2GetRealOutputDerivatives", "maxOutputDerivativeOrder is 0");
}
EXPORT fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean no_set) {
  (void)no_set;
  return (fmi2Status)Step(c, t, h);
}
EXPORT fmi2Status fmi2CancelStep(fmi2Component c) {
  return (fmi2Status)Unsupported(c, "fmi2CancelStep", "fmi2DoStep returns when the step is done");
}
#define STATUS2(call, type)                                                  \
  EXPORT fmi2Status call(fmi2Component c, const fmi2StatusKind s, type* v) { \
    (void)s; (void)v;                                                        \
    if (c != NULL) fmu_log(&((Instance*)c)->host, FMU_DISCARD, "%s: no such status", #call); \
    return fmi2Discard;                                                      \
  }
STATUS2(fmi2GetStatus, fmi2Status)
STATUS2(fmi2GetIntegerStatus, fmi2Integer)
STATUS2(fmi2GetBooleanStatus, fmi2Boolean)
STATUS2(fmi2GetStringStatus, fmi2String)
EXPORT fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real* v) {
  if (c == NULL || s != fmi2LastSuccessfulTime) return fmi2Discard;
  *v = ((Instance*)c)->time;
  return fmi2OK;
}

/* FMI 3.0: the second half of this file (fmu_entry.c stays one translation unit). */
#include "hybridtest/fmi/fmu_entry_fmi3.inc"
