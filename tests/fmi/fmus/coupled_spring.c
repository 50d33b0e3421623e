/* A small FMI 2.0 co-simulation FMU for hybridtest's tests: two coupled linear springs,
 * F = K x with K = [[k11, k12], [k21, k22]], no state (it exports no FMU-state functions and
 * its description declares F1, F2 dependent on x1, x2 only). It serves a substructure of two
 * slots (`slots: [r1, r2]`).
 * Value references: 0 x1, 1 x2 [m] inputs; 2 F1, 3 F2 [N] outputs; 4 k11, 5 k12, 6 k21,
 * 7 k22 [N/m] parameters. FMU_GUID is defined by the build.
 */
#include <stdlib.h>
#include <string.h>

#include "hybridtest/fmi/fmi2_api.h"

#define EXPORT __attribute__((visibility("default")))

typedef struct {
  double v[8]; /* by value reference; v[2], v[3] computed on demand */
} Instance;

EXPORT fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid,
                                     fmi2String resources, const fmi2CallbackFunctions* cb,
                                     fmi2Boolean visible, fmi2Boolean logging) {
  (void)name; (void)resources; (void)cb; (void)visible; (void)logging;
  if (type != fmi2CoSimulation || guid == NULL || strcmp(guid, FMU_GUID) != 0) return NULL;
  Instance* in = (Instance*)calloc(1, sizeof(Instance));
  if (in != NULL) in->v[4] = in->v[7] = 1000.0;
  return in;
}

EXPORT void fmi2FreeInstance(fmi2Component c) { free(c); }
EXPORT fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean a, fmi2Real b, fmi2Real t0,
                                      fmi2Boolean d, fmi2Real e) {
  (void)c; (void)a; (void)b; (void)t0; (void)d; (void)e;
  return fmi2OK;
}
EXPORT fmi2Status fmi2EnterInitializationMode(fmi2Component c) { (void)c; return fmi2OK; }
EXPORT fmi2Status fmi2ExitInitializationMode(fmi2Component c) { (void)c; return fmi2OK; }
EXPORT fmi2Status fmi2Terminate(fmi2Component c) { (void)c; return fmi2OK; }

EXPORT fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                              fmi2Real value[]) {
  const double* v = ((Instance*)c)->v;
  for (size_t i = 0; i < n; ++i) {
    if (vr[i] > 7) return fmi2Error;
    if (vr[i] == 2) {
      value[i] = v[4] * v[0] + v[5] * v[1];
    } else if (vr[i] == 3) {
      value[i] = v[6] * v[0] + v[7] * v[1];
    } else {
      value[i] = v[vr[i]];
    }
  }
  return fmi2OK;
}

EXPORT fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                              const fmi2Real value[]) {
  double* v = ((Instance*)c)->v;
  for (size_t i = 0; i < n; ++i) {
    if (vr[i] > 7 || vr[i] == 2 || vr[i] == 3) return fmi2Error;
    v[vr[i]] = value[i];
  }
  return fmi2OK;
}

EXPORT fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Integer v[]) { (void)c; (void)vr; (void)v; return n == 0 ? fmi2OK : fmi2Error; }
EXPORT fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Boolean v[]) { (void)c; (void)vr; (void)v; return n == 0 ? fmi2OK : fmi2Error; }

EXPORT fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean no_set) {
  (void)c; (void)t; (void)no_set;
  return h > 0.0 ? fmi2OK : fmi2Error;
}
