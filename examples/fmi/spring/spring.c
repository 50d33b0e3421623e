/* examples/fmi/spring: a linear spring as an FMI 2.0 co-simulation FMU, F = k x.
 *
 * The smallest FMU hybridtest can use as a numerical substructure: one input (the slot
 * displacement x [m]), one output (the restoring force F [N]), one parameter (k [N/m]). It has
 * no state, and its modelDescription.xml says so (F depends on x only), so hybridtest needs no
 * get/set FMU state: it sets x and reads F at every trial, and steps the FMU at each commit.
 *
 * This file is the model only: the FMI functions (all of them, FMI 2.0 and 3.0) are
 * hybridtest's shared src/hybridtest/fmi/fmu_entry.c, built with it, which calls the table
 * `fmu_model` at the end of this file (docs/fmi.md, "Writing an FMU").
 *
 * Value references (modelDescription.xml beside this file): 0 x, 1 F, 2 k.
 * Built by examples/fmi/CMakeLists.txt into build/release/examples/fmi/spring.fmu.
 */
#include <stdlib.h>

#include "hybridtest/fmi/fmu_entry.h"

typedef struct {
  double t, x, k;
  const FmuHost* host;
} Spring;

static void* Instantiate(const FmuHost* host, const char* token, const char* resources) {
  (void)token; (void)resources;
  Spring* s = (Spring*)calloc(1, sizeof(Spring));
  if (s == NULL) return NULL;
  s->host = host;
  s->k = 7200.0;
  return s;
}

static void FreeInstance(void* self) { free(self); }

static int Setup(void* self, double start, int stop_defined, double stop) {
  (void)stop_defined; (void)stop;
  ((Spring*)self)->t = start;
  return FMU_OK;
}

static int Get(void* self, const unsigned vr[], size_t n, double value[]) {
  Spring* s = (Spring*)self;
  for (size_t i = 0; i < n; ++i) {
    switch (vr[i]) {
      case 0: value[i] = s->x; break;
      case 1: value[i] = s->k * s->x; break;
      case 2: value[i] = s->k; break;
      default: fmu_log(s->host, FMU_ERROR, "get: no variable has value reference %u", vr[i]); return FMU_ERROR;
    }
  }
  return FMU_OK;
}

static int Set(void* self, const unsigned vr[], size_t n, const double value[]) {
  Spring* s = (Spring*)self;
  for (size_t i = 0; i < n; ++i) {
    switch (vr[i]) {
      case 0: s->x = value[i]; break;
      case 2: s->k = value[i]; break;
      default: fmu_log(s->host, FMU_ERROR, "set: value reference %u cannot be set", vr[i]); return FMU_ERROR;
    }
  }
  return FMU_OK;
}

static int DoStep(void* self, double t, double h, double* time) {
  Spring* s = (Spring*)self;
  if (h <= 0.0) {
    fmu_log(s->host, FMU_ERROR, "DoStep: the communication step must be positive");
    return FMU_ERROR;
  }
  s->t = t + h;
  *time = s->t;
  return FMU_OK;
}

const FmuModel fmu_model = {
    .token = "{hybridtest-example-spring}",
    .instantiate = Instantiate,
    .free_instance = FreeInstance,
    .setup = Setup,
    .get = Get,
    .set = Set,
    .do_step = DoStep,
    /* no save_state / restore_state: no state (canGetAndSetFMUState is false); members left
       out are NULL, and the entry points refuse what they would serve */
};
