#pragma once
// A model's right-hand side compiled to machine code (issue 36 item 3, decision 0019): the C
// that `hybridtest equations --format c` writes, built into a shared library and loaded by
// symbolic/compiled_model.h, which checks it against the numeric engine before attaching it
// to a Model (Model::AttachCompiledRhs). CalcStateDerivative<double> then calls `function` in
// place of CalcKinematics, CalcMassMatrix and CalcForcing; everything else (the factorisation,
// the solve, AutoDiff, the slot displacements) is the engine's own code.
#include <memory>
#include <string>

namespace hybridtest::multibody {

// The generated function: x = [q; u; z] (2n + nz), r (num_slots) [N], t [s]. Writes M (n × n,
// column-major, M u̇ = g), g (n), qdot = W(q) u (n) and zdot (nz), in the model's units.
using CompiledRhsFunction = void (*)(double t, const double* x, const double* r, double* M,
                                     double* g, double* qdot, double* zdot);

struct CompiledRhs {
  CompiledRhsFunction function = nullptr;
  std::shared_ptr<void> library;  // keeps the shared library loaded (dlclose on release)
  std::string path;               // the shared library, for messages and provenance
};

}  // namespace hybridtest::multibody
