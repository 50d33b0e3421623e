#pragma once
// A model's right-hand side compiled to machine code (issue 36 item 3, decision 0019): the C
// that `hybridtest equations --format c` writes, built into a shared library and loaded by
// symbolic/compiled_model.h, which checks it against the numeric engine before attaching it
// to a Model (Model::AttachCompiledRhs). CalcStateDerivative<double> then calls `function` in
// place of CalcKinematics, CalcMassMatrix and CalcForcing, and for a constrained model
// `constraints` in place of CalcConstraints; everything else (the factorisation, the choice of
// dependent speeds, the reduction and its solve, AutoDiff, the slot displacements) is the
// engine's own code (constraints.h).
#include <memory>
#include <string>

namespace hybridtest::multibody {

// The generated function: x = [q; u; z] (2n + nz), r (num_slots) [N], t [s]. Writes M (n × n,
// column-major, M u̇ = g), g (n), qdot = W(q) u (n) and zdot (nz), in the model's units.
using CompiledRhsFunction = void (*)(double t, const double* x, const double* r, double* M,
                                     double* g, double* qdot, double* zdot);

// A constrained model's rows of B u + c = 0 (m = Model::num_constraint_rows()) at x, t, as
// CalcConstraints computes them: B (m × n, column-major), B u + c (m), f(q, t) (m; 0 for the
// non-holonomic rows) and the bias Ḃ u + ċ (m). Units as in constraints.h.
using CompiledConstraintsFunction = void (*)(double t, const double* x, double* B,
                                             double* velocity, double* position, double* bias);

struct CompiledRhs {
  CompiledRhsFunction function = nullptr;
  CompiledConstraintsFunction constraints = nullptr;  // non-null iff the model has constraints
  std::shared_ptr<void> library;  // keeps the shared library loaded (dlclose on release)
  std::string path;               // the shared library, for messages and provenance
};

}  // namespace hybridtest::multibody
