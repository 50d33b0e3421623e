// Evaluation of kinematic fields. See field_eval.h.
#include "hybridtest/multibody/field_eval.h"

#include <cmath>

namespace hybridtest::multibody::internal {

template <typename T>
void SeedCoordinateJets(Data<T>& data, bool rates) {
  for (int k = 0; k < data.n; ++k) {
    Jet<T>& j = data.q_jets[k];
    j.v = data.q(k);
    j.d1 = rates ? data.qdot(k) : T(0.0);
    j.d2 = rates ? data.qddot_rem(k) : T(0.0);
    j.n = data.n;
    for (int i = 0; i < data.n; ++i) j.dq[i] = T(i == k ? 1.0 : 0.0);
  }
}

template <typename T>
FieldEval<T> EvalField(const Model& model, Data<T>& data, const ScalarField& field,
                       T* partial_rate) {
  const int n = data.n;
  const bool identity = model.has_identity_kinematics();
  FieldEval<T> e;
  if (partial_rate != nullptr) {
    for (int j = 0; j < n; ++j) partial_rate[j] = T(0.0);
  }
  if (field.is_affine()) {
    e.v = T(field.constant()) + field.time_rate() * data.t;
    e.d1 = T(field.time_rate());
    for (const auto& term : field.terms()) {
      const int k = term.coordinate;
      const double c = term.coefficient;
      e.v += c * data.q(k);
      e.d1 += c * data.qdot(k);
      if (!identity) e.d2 += c * data.qddot_rem(k);
      if (partial_rate != nullptr) {
        if (identity) {
          partial_rate[k] += T(c);
        } else {
          for (int j = 0; j < n; ++j) partial_rate[j] += c * data.W(k, j);
        }
      }
    }
    return e;
  }
  Jet<T> time;
  time.v = data.t;
  time.d1 = T(1.0);
  const KinematicArgs<T> args{std::span<const Jet<T>>(data.q_jets.data(), n), time};
  const Jet<T> jet = field.function().template get<T>()(args);
  e.v = jet.v;
  e.d1 = jet.d1;
  e.d2 = jet.d2;
  if (partial_rate != nullptr) {
    for (int k = 0; k < jet.n; ++k) {
      if (identity) {
        partial_rate[k] += jet.dq[k];
      } else {
        for (int j = 0; j < n; ++j) partial_rate[j] += jet.dq[k] * data.W(k, j);
      }
    }
  }
  return e;
}

template <typename T>
Matrix3<T> RotationAboutAxis(const Eigen::Vector3d& axis, const T& angle) {
  using std::cos;
  using std::sin;
  const T c = cos(angle);
  const T s = sin(angle);
  const T one_minus_c = 1.0 - c;
  Matrix3<T> R;
  const double x = axis.x(), y = axis.y(), z = axis.z();
  R(0, 0) = c + x * x * one_minus_c;
  R(0, 1) = x * y * one_minus_c - z * s;
  R(0, 2) = x * z * one_minus_c + y * s;
  R(1, 0) = y * x * one_minus_c + z * s;
  R(1, 1) = c + y * y * one_minus_c;
  R(1, 2) = y * z * one_minus_c - x * s;
  R(2, 0) = z * x * one_minus_c - y * s;
  R(2, 1) = z * y * one_minus_c + x * s;
  R(2, 2) = c + z * z * one_minus_c;
  return R;
}

#define HYBRIDTEST_INSTANTIATE(T)                                                         \
  template void SeedCoordinateJets<T>(Data<T>&, bool);                                    \
  template FieldEval<T> EvalField<T>(const Model&, Data<T>&, const ScalarField&, T*);     \
  template Matrix3<T> RotationAboutAxis<T>(const Eigen::Vector3d&, const T&);
HYBRIDTEST_INSTANTIATE(double)
HYBRIDTEST_INSTANTIATE(AutoDiff)
HYBRIDTEST_INSTANTIATE(Symbolic)
#undef HYBRIDTEST_INSTANTIATE

}  // namespace hybridtest::multibody::internal
