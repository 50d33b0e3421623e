/* examples/fmi/spring: a linear spring as an FMI 2.0 co-simulation FMU, F = k x.
 *
 * The smallest FMU hybridtest can use as a numerical substructure: one input (the slot
 * displacement x [m]), one output (the restoring force F [N]), one parameter (k [N/m]). It has
 * no state, and its modelDescription.xml says so (F depends on x only), so hybridtest needs no
 * get/set FMU state: it sets x and reads F at every trial, and steps the FMU at each commit.
 *
 * Value references (modelDescription.xml beside this file): 0 x, 1 F, 2 k.
 * Built by examples/fmi/CMakeLists.txt into build/release/examples/fmi/spring.fmu.
 */
#include <stdlib.h>
#include <string.h>

#include "hybridtest/fmi/fmi2_api.h"

#define EXPORT __attribute__((visibility("default")))
#define GUID "{hybridtest-example-spring}"

typedef struct {
  double t, x, k;
  fmi2CallbackFunctions cb;
  char name[64];
} Spring;

static void Log(Spring* s, fmi2Status status, const char* message) {
  if (s->cb.logger != NULL) {
    s->cb.logger(s->cb.componentEnvironment, s->name, status, "logStatusError", message);
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
  if (cb == NULL || type != fmi2CoSimulation || guid == NULL || strcmp(guid, GUID) != 0) {
    return NULL;
  }
  Spring* s = (Spring*)calloc(1, sizeof(Spring));
  if (s == NULL) return NULL;
  memcpy((void*)&s->cb, cb, sizeof(fmi2CallbackFunctions)); /* its members are const */
  strncpy(s->name, name != NULL ? name : "", sizeof s->name - 1);
  s->k = 7200.0;
  return s;
}

EXPORT void fmi2FreeInstance(fmi2Component c) { free(c); }

EXPORT fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tol_defined, fmi2Real tol,
                                      fmi2Real start, fmi2Boolean stop_defined, fmi2Real stop) {
  (void)tol_defined; (void)tol; (void)stop_defined; (void)stop;
  ((Spring*)c)->t = start;
  return fmi2OK;
}

EXPORT fmi2Status fmi2EnterInitializationMode(fmi2Component c) { (void)c; return fmi2OK; }
EXPORT fmi2Status fmi2ExitInitializationMode(fmi2Component c) { (void)c; return fmi2OK; }
EXPORT fmi2Status fmi2Terminate(fmi2Component c) { (void)c; return fmi2OK; }
EXPORT fmi2Status fmi2Reset(fmi2Component c) { (void)c; return fmi2OK; }

EXPORT fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                              fmi2Real value[]) {
  Spring* s = (Spring*)c;
  for (size_t i = 0; i < n; ++i) {
    switch (vr[i]) {
      case 0: value[i] = s->x; break;
      case 1: value[i] = s->k * s->x; break;
      case 2: value[i] = s->k; break;
      default: Log(s, fmi2Error, "fmi2GetReal: unknown value reference"); return fmi2Error;
    }
  }
  return fmi2OK;
}

EXPORT fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                              const fmi2Real value[]) {
  Spring* s = (Spring*)c;
  for (size_t i = 0; i < n; ++i) {
    switch (vr[i]) {
      case 0: s->x = value[i]; break;
      case 2: s->k = value[i]; break;
      default: Log(s, fmi2Error, "fmi2SetReal: this variable cannot be set"); return fmi2Error;
    }
  }
  return fmi2OK;
}

EXPORT fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Integer v[]) { (void)c; (void)vr; (void)v; return n == 0 ? fmi2OK : fmi2Error; }
EXPORT fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Integer v[]) { (void)c; (void)vr; (void)v; return n == 0 ? fmi2OK : fmi2Error; }
EXPORT fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Boolean v[]) { (void)c; (void)vr; (void)v; return n == 0 ? fmi2OK : fmi2Error; }
EXPORT fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Boolean v[]) { (void)c; (void)vr; (void)v; return n == 0 ? fmi2OK : fmi2Error; }

EXPORT fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean no_set) {
  (void)no_set;
  Spring* s = (Spring*)c;
  if (h <= 0.0) {
    Log(s, fmi2Error, "fmi2DoStep: the communication step must be positive");
    return fmi2Error;
  }
  s->t = t + h;
  return fmi2OK;
}

EXPORT fmi2Status fmi2CancelStep(fmi2Component c) { (void)c; return fmi2Error; }
