#pragma once
// An independent solution of a constrained model's equations for the tests: M u̇ = g + Bᵀλ and
// the acceleration constraints B u̇ = −(Ḃ u + ċ), solved as one augmented system
// [M −Bᵀ; B 0] [u̇; λ] = [g; −bias] by a full-pivot LU (no reduction, no dependent speeds),
// at (t, x) with r = 0, M from the pairwise (not the tree) algorithm.
#include <Eigen/Core>
#include <Eigen/LU>

#include "hybridtest/multibody/constraints.h"
#include "hybridtest/multibody/kane.h"

namespace hybridtest::test_support {

// [u̇ (n); λ (m)] without stabilisation (on the constraint manifold it changes nothing).
inline Eigen::VectorXd AugmentedSolution(const multibody::Model& model, double t,
                                         const Eigen::VectorXd& x) {
  multibody::Data<double> data(model);
  const int n = model.num_coordinates();
  const int m = model.num_constraint_rows();
  multibody::CalcKinematics<double>(model, data, t, x);
  multibody::CalcMassMatrixPairwise(model, data);
  multibody::CalcForcing<double>(model, data, Eigen::VectorXd::Zero(model.num_slots()));
  multibody::CalcConstraints(model, data);
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n + m, n + m);
  K.topLeftCorner(n, n) = data.M;
  K.topRightCorner(n, m) = -data.constraint_B.transpose();
  K.bottomLeftCorner(m, n) = data.constraint_B;
  Eigen::VectorXd rhs(n + m);
  rhs << data.g, -data.constraint_bias;
  return Eigen::FullPivLU<Eigen::MatrixXd>(K).solve(rhs);
}

}  // namespace hybridtest::test_support
