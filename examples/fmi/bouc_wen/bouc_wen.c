/* examples/fmi/bouc_wen: a hysteretic spring (Bouc-Wen) as an FMI 2.0 co-simulation FMU.
 *
 *   F = alpha k x + (1 - alpha) k z
 *   dz/dt = dx/dt [1 - |z / x_y|^n (beta + gamma sign(z dx/dt))],  beta = gamma = 1/2
 *
 * k [N/m] is the initial stiffness, alpha [-] the post-yield stiffness ratio, x_y [m] the
 * yield displacement and n [-] the sharpness of the knee; z [m] is the hysteretic
 * displacement, the FMU's state. fmi2DoStep(t, h) moves x linearly from its value at the end
 * of the last step (x_last, also state) to the input x set before the call and integrates z
 * over that path (RK4 in x, 16 substeps per step).
 *
 * hybridtest tries a substructure several times per step; this FMU supports fmi2GetFMUstate /
 * fmi2SetFMUstate (so every trial starts from the committed state) and serializing its state
 * (so `hybridtest resume` can restore it).
 *
 * Value references (modelDescription.xml beside this file): 0 x [m] input, 1 F [N] output,
 * 2 k [N/m], 3 alpha [-], 4 x_y [m], 5 n [-], 6 z [m] local.
 * Built by examples/fmi/CMakeLists.txt into build/release/examples/fmi/bouc_wen.fmu.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hybridtest/fmi/fmi2_api.h"

#define EXPORT __attribute__((visibility("default")))
#define GUID "{hybridtest-example-bouc-wen}"

typedef struct {      /* the FMU state: everything that changes in a step */
  double t, x, x_last, z;
  double k, alpha, x_y, n;
} State;

typedef struct {
  State s;
  fmi2CallbackFunctions cb;
  char name[64];
} BoucWen;

static void Log(BoucWen* b, fmi2Status status, const char* message) {
  if (b->cb.logger != NULL) {
    b->cb.logger(b->cb.componentEnvironment, b->name, status, "logStatusError", message);
  }
}

static double Force(const State* s) { return s->alpha * s->k * s->x + (1.0 - s->alpha) * s->k * s->z; }

/* dz/dx at z, moving in the direction of dx. */
static double Slope(const State* s, double z, double dx) {
  const double sign = (z * dx) > 0.0 ? 1.0 : ((z * dx) < 0.0 ? -1.0 : 0.0);
  return 1.0 - pow(fabs(z / s->x_y), s->n) * (0.5 + 0.5 * sign);
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
  BoucWen* b = (BoucWen*)calloc(1, sizeof(BoucWen));
  if (b == NULL) return NULL;
  memcpy((void*)&b->cb, cb, sizeof(fmi2CallbackFunctions)); /* its members are const */
  strncpy(b->name, name != NULL ? name : "", sizeof b->name - 1);
  b->s.k = 7200.0;
  b->s.alpha = 0.5;
  b->s.x_y = 0.01;
  b->s.n = 2.0;
  return b;
}

EXPORT void fmi2FreeInstance(fmi2Component c) { free(c); }

EXPORT fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tol_defined, fmi2Real tol,
                                      fmi2Real start, fmi2Boolean stop_defined, fmi2Real stop) {
  (void)tol_defined; (void)tol; (void)stop_defined; (void)stop;
  ((BoucWen*)c)->s.t = start;
  return fmi2OK;
}

EXPORT fmi2Status fmi2EnterInitializationMode(fmi2Component c) { (void)c; return fmi2OK; }

EXPORT fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
  BoucWen* b = (BoucWen*)c;
  if (!(b->s.k > 0.0) || !(b->s.x_y > 0.0) || !(b->s.n >= 1.0) || b->s.alpha < 0.0 ||
      b->s.alpha > 1.0) {
    Log(b, fmi2Error, "parameters out of range: need k > 0, x_y > 0, n >= 1, 0 <= alpha <= 1");
    return fmi2Error;
  }
  b->s.x_last = b->s.x;
  return fmi2OK;
}

EXPORT fmi2Status fmi2Terminate(fmi2Component c) { (void)c; return fmi2OK; }
EXPORT fmi2Status fmi2Reset(fmi2Component c) { (void)c; return fmi2OK; }

static double* Variable(State* s, fmi2ValueReference vr) {
  switch (vr) {
    case 0: return &s->x;
    case 2: return &s->k;
    case 3: return &s->alpha;
    case 4: return &s->x_y;
    case 5: return &s->n;
    case 6: return &s->z;
    default: return NULL;
  }
}

EXPORT fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                              fmi2Real value[]) {
  BoucWen* b = (BoucWen*)c;
  for (size_t i = 0; i < n; ++i) {
    const double* v = Variable(&b->s, vr[i]);
    if (vr[i] == 1) {
      value[i] = Force(&b->s);
    } else if (v != NULL) {
      value[i] = *v;
    } else {
      Log(b, fmi2Error, "fmi2GetReal: unknown value reference");
      return fmi2Error;
    }
  }
  return fmi2OK;
}

EXPORT fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                              const fmi2Real value[]) {
  BoucWen* b = (BoucWen*)c;
  for (size_t i = 0; i < n; ++i) {
    double* v = Variable(&b->s, vr[i]);
    if (v == NULL || vr[i] == 6) {
      Log(b, fmi2Error, "fmi2SetReal: this variable cannot be set");
      return fmi2Error;
    }
    *v = value[i];
  }
  return fmi2OK;
}

EXPORT fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Integer v[]) { (void)c; (void)vr; (void)v; return n == 0 ? fmi2OK : fmi2Error; }
EXPORT fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Integer v[]) { (void)c; (void)vr; (void)v; return n == 0 ? fmi2OK : fmi2Error; }
EXPORT fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Boolean v[]) { (void)c; (void)vr; (void)v; return n == 0 ? fmi2OK : fmi2Error; }
EXPORT fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Boolean v[]) { (void)c; (void)vr; (void)v; return n == 0 ? fmi2OK : fmi2Error; }

EXPORT fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean no_set) {
  (void)no_set;
  BoucWen* b = (BoucWen*)c;
  State* s = &b->s;
  if (h <= 0.0 || fabs(t - s->t) > 1e-9 * (1.0 + fabs(t))) {
    Log(b, fmi2Error, "fmi2DoStep: the step must start at the FMU's time and be positive");
    return fmi2Error;
  }
  const int substeps = 16;
  const double dx = (s->x - s->x_last) / substeps;
  double z = s->z;
  for (int i = 0; i < substeps; ++i) {  /* RK4 of dz/dx along the path */
    const double k1 = Slope(s, z, dx);
    const double k2 = Slope(s, z + 0.5 * dx * k1, dx);
    const double k3 = Slope(s, z + 0.5 * dx * k2, dx);
    const double k4 = Slope(s, z + dx * k3, dx);
    z += dx * (k1 + 2.0 * k2 + 2.0 * k3 + k4) / 6.0;
  }
  s->z = z;
  s->x_last = s->x;
  s->t = t + h;
  return fmi2OK;
}

EXPORT fmi2Status fmi2CancelStep(fmi2Component c) { (void)c; return fmi2Error; }

EXPORT fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate* state) {
  BoucWen* b = (BoucWen*)c;
  if (*state == NULL) *state = b->cb.allocateMemory(1, sizeof(State));
  if (*state == NULL) return fmi2Error;
  memcpy(*state, &b->s, sizeof(State));
  return fmi2OK;
}

EXPORT fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate state) {
  if (state == NULL) return fmi2Error;
  memcpy(&((BoucWen*)c)->s, state, sizeof(State));
  return fmi2OK;
}

EXPORT fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate* state) {
  ((BoucWen*)c)->cb.freeMemory(*state);
  *state = NULL;
  return fmi2OK;
}

EXPORT fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate s, size_t* size) {
  (void)c; (void)s;
  *size = sizeof(State);
  return fmi2OK;
}

EXPORT fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate s, fmi2Byte bytes[],
                                        size_t size) {
  (void)c;
  if (s == NULL || size != sizeof(State)) return fmi2Error;
  memcpy(bytes, s, sizeof(State));
  return fmi2OK;
}

EXPORT fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte bytes[], size_t size,
                                          fmi2FMUstate* s) {
  if (size != sizeof(State) || fmi2GetFMUstate(c, s) != fmi2OK) return fmi2Error;
  memcpy(*s, bytes, size);
  return fmi2OK;
}
