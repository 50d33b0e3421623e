/* A small FMI 2.0 co-simulation FMU for hybridtest's tests: two coupled linear springs,
 * F = K x with K = [[k11, k12], [k21, k22]], no state (its table has no state functions, so the
 * shared entry points refuse get/set FMU state, and its description declares F1, F2 dependent
 * on x1, x2 only). It serves a substructure of two slots (`slots: [r1, r2]`).
 * Value references: 0 x1, 1 x2 [m] inputs; 2 F1, 3 F2 [N] outputs; 4 k11, 5 k12, 6 k21,
 * 7 k22 [N/m] parameters. FMU_GUID is defined by the build; the FMI functions are the shared
 * src/hybridtest/fmi/fmu_entry.c.
 */
#include <stdlib.h>

#include "hybridtest/fmi/fmu_entry.h"

typedef struct {
  double v[8]; /* by value reference; v[2], v[3] computed on demand */
  const FmuHost* host;
} Instance;

static void* Instantiate(const FmuHost* host, const char* token, const char* resources) {
  (void)token; (void)resources;
  Instance* in = (Instance*)calloc(1, sizeof(Instance));
  if (in == NULL) return NULL;
  in->host = host;
  in->v[4] = in->v[7] = 1000.0;
  return in;
}

static void FreeInstance(void* self) { free(self); }

static int Setup(void* self, double start, int stop_defined, double stop) {
  (void)self; (void)start; (void)stop_defined; (void)stop;
  return FMU_OK;
}

static int Get(void* self, const unsigned vr[], size_t n, double value[]) {
  const Instance* in = (const Instance*)self;
  const double* v = in->v;
  for (size_t i = 0; i < n; ++i) {
    if (vr[i] > 7) {
      fmu_log(in->host, FMU_ERROR, "no variable has value reference %u", vr[i]);
      return FMU_ERROR;
    }
    if (vr[i] == 2) {
      value[i] = v[4] * v[0] + v[5] * v[1];
    } else if (vr[i] == 3) {
      value[i] = v[6] * v[0] + v[7] * v[1];
    } else {
      value[i] = v[vr[i]];
    }
  }
  return FMU_OK;
}

static int Set(void* self, const unsigned vr[], size_t n, const double value[]) {
  Instance* in = (Instance*)self;
  for (size_t i = 0; i < n; ++i) {
    if (vr[i] > 7 || vr[i] == 2 || vr[i] == 3) {
      fmu_log(in->host, FMU_ERROR, "value reference %u cannot be set", vr[i]);
      return FMU_ERROR;
    }
    in->v[vr[i]] = value[i];
  }
  return FMU_OK;
}

static int DoStep(void* self, double t, double h, double* time) {
  (void)self;
  *time = t + h;
  return h > 0.0 ? FMU_OK : FMU_ERROR;
}

const FmuModel fmu_model = {
    .token = FMU_GUID,
    .instantiate = Instantiate,
    .free_instance = FreeInstance,
    .setup = Setup,
    .get = Get,
    .set = Set,
    .do_step = DoStep,
};
