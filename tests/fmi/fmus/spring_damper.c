/* A small FMI 2.0 co-simulation FMU for hybridtest's tests: a Maxwell element (a spring k in
 * series with a dashpot c) driven by the displacement x of its free end:
 *
 *   F = k (x - y),   c dy/dt = F   (y: the dashpot's displacement, the state)
 *
 * fmi2DoStep holds x over the step and integrates exactly: y(t + h) = x + (y - x) exp(-k h / c).
 * With c <= 0 the dashpot is rigid (y stays 0): a linear spring F = k x with no state.
 * The parameter fail_at [s] makes fmi2DoStep return fmi2Error (and log why) once a step would
 * reach past it: the error path of the importer.
 *
 * Value references (the modelDescription.xml files beside this file name them):
 *   0 x [m] input, 1 F [N] output, 2 k [N/m], 3 c [N.s/m], 4 fail_at [s], 5 y [m] local,
 *   6 der(y) [m/s] local.
 * One source, several FMUs: each is this file built under its modelIdentifier, with its own
 * modelDescription.xml (which variables and capabilities it declares and its FMI version: the
 * binary exports both the FMI 2.0 and the FMI 3.0 functions). FMU_GUID (the FMI 2 guid or FMI
 * 3 instantiationToken) is defined by the build. The state (get/set/serialize) is the whole
 * instance record.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hybridtest/fmi/fmi2_api.h"
#include "hybridtest/fmi/fmi3_api.h"

#define EXPORT __attribute__((visibility("default")))

typedef struct {
  double t, x, y, k, c, fail_at;
} Record;

typedef struct {
  Record r;
  fmi2CallbackFunctions cb;           /* FMI 2 */
  fmi3InstanceEnvironment env3;       /* FMI 3 */
  fmi3LogMessageCallback log3;
  char name[64];
} Instance;

static double Force(const Record* r) { return r->k * (r->x - r->y); }

static void Log(Instance* in, fmi2Status s, const char* category, const char* message, double v) {
  if (in->cb.logger != NULL) in->cb.logger(in->cb.componentEnvironment, in->name, s, category, message, v);
  if (in->log3 != NULL) {
    char text[256];
    snprintf(text, sizeof text, message, v);
    in->log3(in->env3, (fmi3Status)s, category, text);
  }
}

EXPORT const char* fmi2GetTypesPlatform(void) { return "default"; }
EXPORT const char* fmi2GetVersion(void) { return "2.0"; }

EXPORT fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean on, size_t n,
                                      const fmi2String categories[]) {
  (void)c; (void)on; (void)n; (void)categories;
  return fmi2OK;
}

EXPORT fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid,
                                     fmi2String resources, const fmi2CallbackFunctions* cb,
                                     fmi2Boolean visible, fmi2Boolean logging) {
  (void)resources; (void)visible; (void)logging;
  if (type != fmi2CoSimulation || guid == NULL || strcmp(guid, FMU_GUID) != 0) {
    if (cb != NULL && cb->logger != NULL) {
      cb->logger(cb->componentEnvironment, name, fmi2Error, "logStatusError",
                 "wrong type or guid '%s' (expected %s)", guid ? guid : "", FMU_GUID);
    }
    return NULL;
  }
  Instance* in = (Instance*)calloc(1, sizeof(Instance));
  if (in == NULL) return NULL;
  memcpy((void*)&in->cb, cb, sizeof(fmi2CallbackFunctions));
  strncpy(in->name, name ? name : "", sizeof in->name - 1);
  in->r.k = 1000.0;
  in->r.c = 0.0;
  in->r.fail_at = 1e300;
  return in;
}

EXPORT void fmi2FreeInstance(fmi2Component c) { free(c); }

EXPORT fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tol_defined, fmi2Real tol,
                                      fmi2Real start, fmi2Boolean stop_defined, fmi2Real stop) {
  (void)tol_defined; (void)tol; (void)stop_defined; (void)stop;
  ((Instance*)c)->r.t = start;
  return fmi2OK;
}

EXPORT fmi2Status fmi2EnterInitializationMode(fmi2Component c) { (void)c; return fmi2OK; }
EXPORT fmi2Status fmi2ExitInitializationMode(fmi2Component c) { (void)c; return fmi2OK; }
EXPORT fmi2Status fmi2Terminate(fmi2Component c) { (void)c; return fmi2OK; }
EXPORT fmi2Status fmi2Reset(fmi2Component c) { (void)c; return fmi2OK; }

static double* Slot(Record* r, fmi2ValueReference vr) {
  switch (vr) {
    case 0: return &r->x;
    case 2: return &r->k;
    case 3: return &r->c;
    case 4: return &r->fail_at;
    case 5: return &r->y;
    default: return NULL;
  }
}

EXPORT fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                              fmi2Real value[]) {
  Record* r = &((Instance*)c)->r;
  for (size_t i = 0; i < n; ++i) {
    if (vr[i] == 1) {
      value[i] = Force(r);
    } else if (vr[i] == 6) {
      value[i] = r->c > 0.0 ? Force(r) / r->c : 0.0;
    } else {
      double* p = Slot(r, vr[i]);
      if (p == NULL) return fmi2Error;
      value[i] = *p;
    }
  }
  return fmi2OK;
}

EXPORT fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                              const fmi2Real value[]) {
  Instance* in = (Instance*)c;
  for (size_t i = 0; i < n; ++i) {
    double* p = Slot(&in->r, vr[i]);
    if (p == NULL || vr[i] == 5) {
      Log(in, fmi2Error, "logStatusError", "value reference %g cannot be set", (double)vr[i]);
      return fmi2Error;
    }
    *p = value[i];
  }
  return fmi2OK;
}

EXPORT fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Integer v[]) { (void)c; (void)vr; (void)v; return n == 0 ? fmi2OK : fmi2Error; }
EXPORT fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Integer v[]) { (void)c; (void)vr; (void)v; return n == 0 ? fmi2OK : fmi2Error; }
EXPORT fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Boolean v[]) { (void)c; (void)vr; (void)v; return n == 0 ? fmi2OK : fmi2Error; }
EXPORT fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Boolean v[]) { (void)c; (void)vr; (void)v; return n == 0 ? fmi2OK : fmi2Error; }

EXPORT fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean no_set) {
  (void)no_set;
  Instance* in = (Instance*)c;
  Record* r = &in->r;
  if (fabs(t - r->t) > 1e-9 * (1.0 + fabs(t))) {
    Log(in, fmi2Error, "logStatusError", "communication point %g s is not the FMU's time", t);
    return fmi2Error;
  }
  if (t + h > r->fail_at) {
    Log(in, fmi2Error, "logStatusError", "fail_at reached: the step ends at %g s", t + h);
    return fmi2Error;
  }
  if (r->c > 0.0) r->y = r->x + (r->y - r->x) * exp(-r->k * h / r->c);
  r->t = t + h;
  return fmi2OK;
}

EXPORT fmi2Status fmi2CancelStep(fmi2Component c) { (void)c; return fmi2Error; }

EXPORT fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate* state) {
  Instance* in = (Instance*)c;
  if (*state == NULL) *state = in->cb.allocateMemory(1, sizeof(Record));
  if (*state == NULL) return fmi2Error;
  memcpy(*state, &in->r, sizeof(Record));
  return fmi2OK;
}

EXPORT fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate state) {
  if (state == NULL) return fmi2Error;
  memcpy(&((Instance*)c)->r, state, sizeof(Record));
  return fmi2OK;
}

EXPORT fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate* state) {
  ((Instance*)c)->cb.freeMemory(*state);
  *state = NULL;
  return fmi2OK;
}

EXPORT fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate s, size_t* size) {
  (void)c; (void)s;
  *size = sizeof(Record);
  return fmi2OK;
}

EXPORT fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate s, fmi2Byte bytes[],
                                        size_t size) {
  (void)c;
  if (size != sizeof(Record)) return fmi2Error;
  memcpy(bytes, s, sizeof(Record));
  return fmi2OK;
}

EXPORT fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte bytes[], size_t size,
                                          fmi2FMUstate* s) {
  if (size != sizeof(Record)) return fmi2Error;
  return fmi2GetFMUstate(c, s) == fmi2OK ? (memcpy(*s, bytes, size), fmi2OK) : fmi2Error;
}

/* FMI 3.0: the same element behind the FMI 3 functions (value references as above). */

EXPORT fmi3Instance fmi3InstantiateCoSimulation(
    fmi3String name, fmi3String token, fmi3String resources, fmi3Boolean visible,
    fmi3Boolean logging, fmi3Boolean event_mode, fmi3Boolean early_return,
    const fmi3ValueReference required[], size_t n_required, fmi3InstanceEnvironment env,
    fmi3LogMessageCallback log, fmi3IntermediateUpdateCallback update) {
  (void)resources; (void)visible; (void)logging; (void)event_mode; (void)early_return;
  (void)required; (void)n_required; (void)update;
  if (token == NULL || strcmp(token, FMU_GUID) != 0) {
    if (log != NULL) log(env, fmi3Error, "logStatusError", "wrong instantiationToken");
    return NULL;
  }
  Instance* in = (Instance*)calloc(1, sizeof(Instance));
  if (in == NULL) return NULL;
  in->env3 = env;
  in->log3 = log;
  strncpy(in->name, name ? name : "", sizeof in->name - 1);
  in->r.k = 1000.0;
  in->r.c = 0.0;
  in->r.fail_at = 1e300;
  return in;
}

EXPORT void fmi3FreeInstance(fmi3Instance c) { free(c); }

EXPORT fmi3Status fmi3EnterInitializationMode(fmi3Instance c, fmi3Boolean tol_defined,
                                              fmi3Float64 tol, fmi3Float64 start,
                                              fmi3Boolean stop_defined, fmi3Float64 stop) {
  (void)tol_defined; (void)tol; (void)stop_defined; (void)stop;
  ((Instance*)c)->r.t = start;
  return fmi3OK;
}
EXPORT fmi3Status fmi3ExitInitializationMode(fmi3Instance c) { (void)c; return fmi3OK; }
EXPORT fmi3Status fmi3Terminate(fmi3Instance c) { (void)c; return fmi3OK; }

EXPORT fmi3Status fmi3GetFloat64(fmi3Instance c, const fmi3ValueReference vr[], size_t n,
                                 fmi3Float64 values[], size_t n_values) {
  if (n != n_values) return fmi3Error;
  return (fmi3Status)fmi2GetReal(c, vr, n, values);
}
EXPORT fmi3Status fmi3SetFloat64(fmi3Instance c, const fmi3ValueReference vr[], size_t n,
                                 const fmi3Float64 values[], size_t n_values) {
  if (n != n_values) return fmi3Error;
  return (fmi3Status)fmi2SetReal(c, vr, n, values);
}
EXPORT fmi3Status fmi3SetInt32(fmi3Instance c, const fmi3ValueReference vr[], size_t n,
                               const fmi3Int32 values[], size_t n_values) {
  (void)c; (void)vr; (void)values; (void)n_values;
  return n == 0 ? fmi3OK : fmi3Error;
}
EXPORT fmi3Status fmi3SetBoolean(fmi3Instance c, const fmi3ValueReference vr[], size_t n,
                                 const fmi3Boolean values[], size_t n_values) {
  (void)c; (void)vr; (void)values; (void)n_values;
  return n == 0 ? fmi3OK : fmi3Error;
}

EXPORT fmi3Status fmi3DoStep(fmi3Instance c, fmi3Float64 t, fmi3Float64 h, fmi3Boolean no_set,
                             fmi3Boolean* event, fmi3Boolean* terminate, fmi3Boolean* early,
                             fmi3Float64* last) {
  const fmi2Status s = fmi2DoStep(c, t, h, no_set);
  *event = false;
  *terminate = false;
  *early = false;
  *last = ((Instance*)c)->r.t;
  return (fmi3Status)s;
}

EXPORT fmi3Status fmi3GetFMUState(fmi3Instance c, fmi3FMUState* state) {
  if (*state == NULL) *state = malloc(sizeof(Record));
  if (*state == NULL) return fmi3Error;
  memcpy(*state, &((Instance*)c)->r, sizeof(Record));
  return fmi3OK;
}
EXPORT fmi3Status fmi3SetFMUState(fmi3Instance c, fmi3FMUState state) {
  return (fmi3Status)fmi2SetFMUstate(c, state);
}
EXPORT fmi3Status fmi3FreeFMUState(fmi3Instance c, fmi3FMUState* state) {
  (void)c;
  free(*state);
  *state = NULL;
  return fmi3OK;
}
EXPORT fmi3Status fmi3SerializedFMUStateSize(fmi3Instance c, fmi3FMUState s, size_t* size) {
  return (fmi3Status)fmi2SerializedFMUstateSize(c, s, size);
}
EXPORT fmi3Status fmi3SerializeFMUState(fmi3Instance c, fmi3FMUState s, fmi3Byte bytes[],
                                        size_t size) {
  return (fmi3Status)fmi2SerializeFMUstate(c, s, (fmi2Byte*)bytes, size);
}
EXPORT fmi3Status fmi3DeserializeFMUState(fmi3Instance c, const fmi3Byte bytes[], size_t size,
                                          fmi3FMUState* s) {
  if (size != sizeof(Record)) return fmi3Error;
  if (fmi3GetFMUState(c, s) != fmi3OK) return fmi3Error;
  memcpy(*s, bytes, size);
  return fmi3OK;
}
