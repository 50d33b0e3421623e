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
 * This file is the model only: the FMI functions (all of them, FMI 2.0 and 3.0) are
 * hybridtest's shared src/hybridtest/fmi/fmu_entry.c, built with it, which calls the table
 * `fmu_model` at the end of this file.
 *
 * Value references (modelDescription.xml beside this file): 0 x [m] input, 1 F [N] output,
 * 2 k [N/m], 3 alpha [-], 4 x_y [m], 5 n [-], 6 z [m] local.
 * Built by examples/fmi/CMakeLists.txt into build/release/examples/fmi/bouc_wen.fmu.
 */
#include <math.h>
#include <stdlib.h>

#include "hybridtest/fmi/fmu_entry.h"

typedef struct {      /* the FMU state: everything that changes in a step */
  double t, x, x_last, z;
  double k, alpha, x_y, n;
} State;

typedef struct {
  State s;
  const FmuHost* host;
} BoucWen;

static double Force(const State* s) { return s->alpha * s->k * s->x + (1.0 - s->alpha) * s->k * s->z; }

/* dz/dx at z, moving in the direction of dx. */
static double Slope(const State* s, double z, double dx) {
  const double sign = (z * dx) > 0.0 ? 1.0 : ((z * dx) < 0.0 ? -1.0 : 0.0);
  return 1.0 - pow(fabs(z / s->x_y), s->n) * (0.5 + 0.5 * sign);
}

static void* Instantiate(const FmuHost* host, const char* token, const char* resources) {
  (void)token; (void)resources;
  BoucWen* b = (BoucWen*)calloc(1, sizeof(BoucWen));
  if (b == NULL) return NULL;
  b->host = host;
  b->s.k = 7200.0;
  b->s.alpha = 0.5;
  b->s.x_y = 0.01;
  b->s.n = 2.0;
  return b;
}

static void FreeInstance(void* self) { free(self); }

static int Setup(void* self, double start, int stop_defined, double stop) {
  (void)stop_defined; (void)stop;
  ((BoucWen*)self)->s.t = start;
  return FMU_OK;
}

static int ExitInitialization(void* self) {
  BoucWen* b = (BoucWen*)self;
  if (!(b->s.k > 0.0) || !(b->s.x_y > 0.0) || !(b->s.n >= 1.0) || b->s.alpha < 0.0 ||
      b->s.alpha > 1.0) {
    fmu_log(b->host, FMU_ERROR, "parameters out of range: need k > 0, x_y > 0, n >= 1, 0 <= alpha <= 1");
    return FMU_ERROR;
  }
  b->s.x_last = b->s.x;
  return FMU_OK;
}

static double* Variable(State* s, unsigned vr) {
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

static int Get(void* self, const unsigned vr[], size_t n, double value[]) {
  BoucWen* b = (BoucWen*)self;
  for (size_t i = 0; i < n; ++i) {
    const double* v = Variable(&b->s, vr[i]);
    if (vr[i] == 1) {
      value[i] = Force(&b->s);
    } else if (v != NULL) {
      value[i] = *v;
    } else {
      fmu_log(b->host, FMU_ERROR, "get: no variable has value reference %u", vr[i]);
      return FMU_ERROR;
    }
  }
  return FMU_OK;
}

static int Set(void* self, const unsigned vr[], size_t n, const double value[]) {
  BoucWen* b = (BoucWen*)self;
  for (size_t i = 0; i < n; ++i) {
    double* v = Variable(&b->s, vr[i]);
    if (v == NULL || vr[i] == 6) {
      fmu_log(b->host, FMU_ERROR, "set: value reference %u cannot be set", vr[i]);
      return FMU_ERROR;
    }
    *v = value[i];
  }
  return FMU_OK;
}

static int DoStep(void* self, double t, double h, double* time) {
  BoucWen* b = (BoucWen*)self;
  State* s = &b->s;
  if (h <= 0.0 || fabs(t - s->t) > 1e-9 * (1.0 + fabs(t))) {
    fmu_log(b->host, FMU_ERROR, "DoStep: the step must start at the FMU's time and be positive");
    return FMU_ERROR;
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
  *time = s->t;
  return FMU_OK;
}

static int SaveState(void* self, void** bytes, size_t* size) {
  return fmu_save_record(&((BoucWen*)self)->s, sizeof(State), bytes, size);
}

static int RestoreState(void* self, const void* bytes, size_t size) {
  BoucWen* b = (BoucWen*)self;
  return fmu_restore_record(b->host, &b->s, sizeof(State), bytes, size);
}

const FmuModel fmu_model = {
    .token = "{hybridtest-example-bouc-wen}",
    .instantiate = Instantiate,
    .free_instance = FreeInstance,
    .setup = Setup,
    .exit_initialization = ExitInitialization,
    .get = Get,
    .set = Set,
    .do_step = DoStep,
    .save_state = SaveState,
    .restore_state = RestoreState,
};
