/* A small co-simulation FMU for hybridtest's tests: a Maxwell element (a spring k in series
 * with a dashpot c) driven by the displacement x of its free end:
 *
 *   F = k (x - y),   c dy/dt = F   (y: the dashpot's displacement, the state)
 *
 * DoStep holds x over the step and integrates exactly: y(t + h) = x + (y - x) exp(-k h / c).
 * With c <= 0 the dashpot is rigid (y stays 0): a linear spring F = k x with no state.
 * The parameter fail_at [s] makes DoStep return Error (and log why) once a step would reach
 * past it: the error path of the importer.
 *
 * Value references (the modelDescription.xml files beside this file name them):
 *   0 x [m] input, 1 F [N] output, 2 k [N/m], 3 c [N.s/m], 4 fail_at [s], 5 y [m] local,
 *   6 der(y) [m/s] local.
 * One source, several FMUs: each is this file built under its modelIdentifier, with its own
 * modelDescription.xml (which variables and capabilities it declares and its FMI version), and
 * with the shared entry points src/hybridtest/fmi/fmu_entry.c (every FMI 2.0 and 3.0
 * function). FMU_GUID (the FMI 2 guid or FMI 3 instantiationToken) is defined by the build.
 * The state (get/set/serialize) is the whole record.
 */
#include <math.h>
#include <stdlib.h>

#include "hybridtest/fmi/fmu_entry.h"

typedef struct {
  double t, x, y, k, c, fail_at;
} Record;

typedef struct {
  Record r;
  const FmuHost* host;
} Instance;

static double Force(const Record* r) { return r->k * (r->x - r->y); }

/* The record as instantiated (and as fmi2Reset / fmi3Reset leaves it). */
static int Reset(void* self) {
  Record* r = &((Instance*)self)->r;
  const Record start = {.t = 0.0, .x = 0.0, .y = 0.0, .k = 1000.0, .c = 0.0, .fail_at = 1e300};
  *r = start;
  return FMU_OK;
}

static void* Instantiate(const FmuHost* host, const char* token, const char* resources) {
  (void)token; (void)resources;
  Instance* in = (Instance*)calloc(1, sizeof(Instance));
  if (in == NULL) return NULL;
  in->host = host;
  Reset(in);
  return in;
}

static void FreeInstance(void* self) { free(self); }

static int Setup(void* self, double start, int stop_defined, double stop) {
  (void)stop_defined; (void)stop;
  ((Instance*)self)->r.t = start;
  return FMU_OK;
}

static double* Slot(Record* r, unsigned vr) {
  switch (vr) {
    case 0: return &r->x;
    case 2: return &r->k;
    case 3: return &r->c;
    case 4: return &r->fail_at;
    case 5: return &r->y;
    default: return NULL;
  }
}

static int Get(void* self, const unsigned vr[], size_t n, double value[]) {
  Instance* in = (Instance*)self;
  Record* r = &in->r;
  for (size_t i = 0; i < n; ++i) {
    if (vr[i] == 1) {
      value[i] = Force(r);
    } else if (vr[i] == 6) {
      value[i] = r->c > 0.0 ? Force(r) / r->c : 0.0;
    } else {
      double* p = Slot(r, vr[i]);
      if (p == NULL) {
        fmu_log(in->host, FMU_ERROR, "no variable has value reference %u", vr[i]);
        return FMU_ERROR;
      }
      value[i] = *p;
    }
  }
  return FMU_OK;
}

static int Set(void* self, const unsigned vr[], size_t n, const double value[]) {
  Instance* in = (Instance*)self;
  for (size_t i = 0; i < n; ++i) {
    double* p = Slot(&in->r, vr[i]);
    if (p == NULL || vr[i] == 5) {
      fmu_log(in->host, FMU_ERROR, "value reference %u cannot be set", vr[i]);
      return FMU_ERROR;
    }
    *p = value[i];
  }
  return FMU_OK;
}

static int DoStep(void* self, double t, double h, double* time) {
  Instance* in = (Instance*)self;
  Record* r = &in->r;
  if (fabs(t - r->t) > 1e-9 * (1.0 + fabs(t))) {
    fmu_log(in->host, FMU_ERROR, "communication point %g s is not the FMU's time", t);
    return FMU_ERROR;
  }
  if (t + h > r->fail_at) {
    fmu_log(in->host, FMU_ERROR, "fail_at reached: the step ends at %g s", t + h);
    return FMU_ERROR;
  }
  if (r->c > 0.0) r->y = r->x + (r->y - r->x) * exp(-r->k * h / r->c);
  r->t = t + h;
  *time = r->t;
  return FMU_OK;
}

static int SaveState(void* self, void** bytes, size_t* size) {
  return fmu_save_record(&((Instance*)self)->r, sizeof(Record), bytes, size);
}

static int RestoreState(void* self, const void* bytes, size_t size) {
  Instance* in = (Instance*)self;
  return fmu_restore_record(in->host, &in->r, sizeof(Record), bytes, size);
}

const FmuModel fmu_model = {
    .token = FMU_GUID,
    .instantiate = Instantiate,
    .free_instance = FreeInstance,
    .setup = Setup,
    .get = Get,
    .set = Set,
    .do_step = DoStep,
    .reset = Reset,
    .save_state = SaveState,
    .restore_state = RestoreState,
};
