#pragma once
// Exact derivatives of the equations of motion without heap allocation: a workspace built
// once from the model, then the state Jacobian J = ∂f_rhs/∂x (nx × nx, nx = 2n + nz) and the hybrid coupling
// matrix B = ∂g/∂r (n × num_slots), as often as needed (e.g. in every step of an implicit or
// partitioned scheme).
//
// Forward-mode AutoDiff carries at most kMaxDerivatives directions inline, so the columns are
// computed in chunks of kMaxDerivatives: J costs ⌈nx / kMaxDerivatives⌉ AutoDiff evaluations
// of f_rhs, B costs ⌈num_slots / kMaxDerivatives⌉ of g. No cap on n or num_slots beyond the
// model's own (kMaxJetCoordinates for models with general fields, model.h).
//
//   DerivativeWorkspace ws(model);                 // allocates, once
//   CalcStateJacobian(model, ws, t, x, r, J);      // J: nx × nx, preallocated
//   CalcCouplingMatrix(model, ws, t, x, B);        // B: n × num_slots, preallocated
#include "hybridtest/multibody/kane.h"

namespace hybridtest::multibody {

class DerivativeWorkspace {
 public:
  explicit DerivativeWorkspace(const Model& model);

  Data<AutoDiff> data;
  VectorX<AutoDiff> x;     // (nx) seeded state
  VectorX<AutoDiff> r;     // (num_slots) seeded restoring forces
  VectorX<AutoDiff> xdot;  // (nx)
};

// J = ∂f_rhs/∂x (nx × nx) at (t, x, r), exact. `J` must be nx × nx. Throws ModelError where
// CalcStateDerivative does (M not positive definite).
void CalcStateJacobian(const Model& model, DerivativeWorkspace& ws, double t,
                       const Eigen::Ref<const Eigen::VectorXd>& x,
                       const Eigen::Ref<const Eigen::VectorXd>& r, Eigen::Ref<Eigen::MatrixXd> J);

// B = ∂g/∂r (n × num_slots) at (t, x): the generalized force of a unit restoring force in each
// slot. Exact; g is affine in r, so B does not depend on r. `B` must be n × num_slots.
void CalcCouplingMatrix(const Model& model, DerivativeWorkspace& ws, double t,
                        const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::MatrixXd> B);

}  // namespace hybridtest::multibody
