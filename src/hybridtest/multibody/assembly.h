#pragma once
// Consistent states and linearisation of a constrained model (constraints.h).
//
// AssembleState: with the independent coordinates held, Newton's method on the dependent
// coordinates (ConstraintOptions::dependent_coordinates, or picked by complete pivoting of
// ∂f/∂q) solves the holonomic constraints f(q, t) = 0 to ConstraintOptions::tolerance or
// better; then the dependent speeds solve B u + c = 0 for the given independent speeds. A
// configuration that cannot satisfy the constraints is refused (ModelError) with the worst
// row, its residual and the tolerance. Cost: a few kinematics evaluations per iteration.
//
// LinearizeConstrained: the state matrix in the independent states x_i = [q_i; u_i; z],
//   A = P J T,  J = ∂ẋ/∂x (exact, AutoDiff through the constraints),
// T = ∂x/∂x_i the tangent of the constraint manifold (δq_d = −f_qd⁻¹ f_qi δq_i and
// δu_d = −B_d⁻¹ (B_i δu_i + ∂(B u + c)/∂q δq)), P the rows of the independent states: the
// chain rule through the dependent q and u, as SymPy's Linearizer does.
#include <string>
#include <vector>

#include "hybridtest/multibody/model.h"

namespace hybridtest::multibody {

struct AssembledState {
  Eigen::VectorXd x;                      // (2n + nz) consistent state
  std::vector<int> dependent_coordinates; // (holonomic rows)
  double position_residual = 0.0;         // max |f| after assembly [m or rad]
  double velocity_residual = 0.0;         // max |B u + c| after assembly
};

// x (2n + nz): the independent coordinates and speeds are kept, the dependent ones solved.
AssembledState AssembleState(const Model& model, double t, const Eigen::VectorXd& x);

// The largest |f| (holonomic rows) and |B u + c| at (t, x), and the row of the worst f.
struct ConstraintResiduals {
  double position = 0.0;
  double velocity = 0.0;
  int worst_row = -1;
};
ConstraintResiduals CalcConstraintResiduals(const Model& model, double t,
                                            const Eigen::VectorXd& x);

struct Linearization {
  Eigen::MatrixXd A;                     // state matrix in the independent states
  std::vector<int> states;               // indices in x of the independent states
  std::vector<std::string> state_names;  // their names (coordinates, speeds, states)
  Eigen::MatrixXd J;                     // (nx × nx) ∂ẋ/∂x with r = k d(q), exact
  Eigen::MatrixXd T;                     // (nx × ni) ∂x/∂x_i, the constraint manifold's tangent
};

// At a consistent state x (AssembleState), with the slots closed by r = k d(q) (k =
// `slot_stiffness`, one per slot; empty: r = 0). Unconstrained models give J itself (every
// state independent).
Linearization LinearizeConstrained(const Model& model, double t, const Eigen::VectorXd& x,
                                   const std::vector<double>& slot_stiffness);

}  // namespace hybridtest::multibody
