#pragma once
// Internal to the engine: evaluation of ScalarFields and rotations on a Data<T> workspace.
#include "hybridtest/multibody/data.h"

namespace hybridtest::multibody::internal {

// φ, φ̇ and φ̈ (with u̇ = 0) of a field at the state held in data.
template <typename T>
struct FieldEval {
  T v{0.0};
  T d1{0.0};
  T d2{0.0};
};

// Evaluates `field` at data's state. If `partial_rate` is not null it receives, for all n
// speeds, ∂φ̇/∂u_j = Σ_k ∂φ/∂q_k W_kj (entries for speeds the field does not depend on are 0).
template <typename T>
FieldEval<T> EvalField(const Model& model, Data<T>& data, const ScalarField& field,
                       T* partial_rate);

// Rotation matrix about the unit `axis` by `angle` (columns: rotated unit vectors).
template <typename T>
Matrix3<T> RotationAboutAxis(const Eigen::Vector3d& axis, const T& angle);

// R v for a 3 × 3 matrix and a 3-vector, inline as a combination of R's columns (Eigen's
// 3 × 3 product is an out-of-line loop here; this is on the kinematics' hot path).
template <typename T>
inline Vector3<T> Multiply(const Matrix3<T>& R, const Vector3<T>& v) {
  return R.col(0) * v(0) + R.col(1) * v(1) + R.col(2) * v(2);
}

// Fills data.q_jets from data.q, data.qdot, data.qddot_rem (value-only seeds if `rates` is false).
template <typename T>
void SeedCoordinateJets(Data<T>& data, bool rates);

}  // namespace hybridtest::multibody::internal
