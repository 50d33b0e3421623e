#pragma once
// Internal to the engine: evaluation of ScalarFields and rotations on a Data<T> workspace.
#include <algorithm>
#include <cstddef>
#include <type_traits>

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

// Scalar 3-vector kernels on raw storage (column-major 3 × k blocks, Vector3 data()): on the
// hot path, Eigen evaluates 3-element expressions with mixed packet and scalar stores that
// stall the loads right after them. Same terms in the same order as the Eigen expressions.
//
// Every operation goes through Mul/Scale/Add/Sub, which return a plain T: AutoDiff's operators
// return expressions whose derivative vectors must have equal sizes, which only plain values
// make so (a value that depends on nothing has an empty vector, resized on first use). For
// double they are the bare operations.
template <typename T>
inline T Mul(const T& a, const T& b) {
  return a * b;
}
template <typename T>
inline T Scale(double c, const T& a) {
  return c * a;
}
template <typename T>
inline T Add(const T& a, const T& b) {
  return a + b;
}
template <typename T>
inline T Sub(const T& a, const T& b) {
  return a - b;
}
template <typename T>
inline void Cross(const T* a, const T* b, T* out) {  // out = a × b; out must not alias a, b
  out[0] = Sub(Mul(a[1], b[2]), Mul(a[2], b[1]));
  out[1] = Sub(Mul(a[2], b[0]), Mul(a[0], b[2]));
  out[2] = Sub(Mul(a[0], b[1]), Mul(a[1], b[0]));
}
template <typename T>
inline T Dot(const T* a, const T* b) {
  return Add(Add(Mul(a[0], b[0]), Mul(a[1], b[1])), Mul(a[2], b[2]));
}
template <typename T>
inline void Copy3(const T* a, T* out) {
  out[0] = a[0];
  out[1] = a[1];
  out[2] = a[2];
}

// dst[0..n) = src[0..n) and dst[0..n) = 0 for the short vectors and 4 × 4 matrices of a small
// model: one jump into a run of stores up to 16 entries (a runtime-sized loop would become a
// call to memmove or memset, which costs more than the copy; a compare and branch per entry
// costs twice the stores), std::copy_n / std::fill_n beyond. Always inline: out of line, the call
// costs as much as the copy (callgrind).
template <typename T>
[[gnu::always_inline]] inline void CopyN(const T* src, std::ptrdiff_t n, T* dst) {
  if constexpr (std::is_same_v<T, double>) {
    switch (n) {
      case 16: dst[15] = src[15]; [[fallthrough]];
      case 15: dst[14] = src[14]; [[fallthrough]];
      case 14: dst[13] = src[13]; [[fallthrough]];
      case 13: dst[12] = src[12]; [[fallthrough]];
      case 12: dst[11] = src[11]; [[fallthrough]];
      case 11: dst[10] = src[10]; [[fallthrough]];
      case 10: dst[9] = src[9]; [[fallthrough]];
      case 9: dst[8] = src[8]; [[fallthrough]];
      case 8: dst[7] = src[7]; [[fallthrough]];
      case 7: dst[6] = src[6]; [[fallthrough]];
      case 6: dst[5] = src[5]; [[fallthrough]];
      case 5: dst[4] = src[4]; [[fallthrough]];
      case 4: dst[3] = src[3]; [[fallthrough]];
      case 3: dst[2] = src[2]; [[fallthrough]];
      case 2: dst[1] = src[1]; [[fallthrough]];
      case 1: dst[0] = src[0]; [[fallthrough]];
      case 0: return;
      default: break;
    }
  }
  std::copy_n(src, n, dst);
}
template <typename T>
[[gnu::always_inline]] inline void ZeroN(std::ptrdiff_t n, T* dst) {
  if constexpr (std::is_same_v<T, double>) {
    switch (n) {
      case 16: dst[15] = 0.0; [[fallthrough]];
      case 15: dst[14] = 0.0; [[fallthrough]];
      case 14: dst[13] = 0.0; [[fallthrough]];
      case 13: dst[12] = 0.0; [[fallthrough]];
      case 12: dst[11] = 0.0; [[fallthrough]];
      case 11: dst[10] = 0.0; [[fallthrough]];
      case 10: dst[9] = 0.0; [[fallthrough]];
      case 9: dst[8] = 0.0; [[fallthrough]];
      case 8: dst[7] = 0.0; [[fallthrough]];
      case 7: dst[6] = 0.0; [[fallthrough]];
      case 6: dst[5] = 0.0; [[fallthrough]];
      case 5: dst[4] = 0.0; [[fallthrough]];
      case 4: dst[3] = 0.0; [[fallthrough]];
      case 3: dst[2] = 0.0; [[fallthrough]];
      case 2: dst[1] = 0.0; [[fallthrough]];
      case 1: dst[0] = 0.0; [[fallthrough]];
      case 0: return;
      default: break;
    }
  }
  std::fill_n(dst, n, T(0.0));
}

// The relative position r = offset + time_rate t + Σ c_k q_k of an affine point
// (CompiledPoint::affine) and its rate as seen in its frame, ṙ = time_rate + Σ c_k q̇_k, in
// E components, into r[3] and rd[3]. The sums run in registers: a store to r[component] read
// back by the next term or by the rotation after it is a chain through memory (measured on
// the rotor). Same terms in the same order as summing into the arrays. Always inline: GCC
// otherwise calls it out of line from the planar point kernel's six instances (callgrind).
template <typename T>
[[gnu::always_inline]] inline void AffinePointOffset(const CompiledPoint& pt, const T& t, const T* q, const T* qdot,
                              T* r, T* rd) {
  T r0 = T(pt.offset(0)), r1 = T(pt.offset(1)), r2 = T(pt.offset(2));
  T d0 = T(pt.time_rate(0)), d1 = T(pt.time_rate(1)), d2 = T(pt.time_rate(2));
  if (pt.has_time_rate) {
    r0 = Add(r0, Scale(pt.time_rate(0), t));
    r1 = Add(r1, Scale(pt.time_rate(1), t));
    r2 = Add(r2, Scale(pt.time_rate(2), t));
  }
  for (const auto& term : pt.rate_terms) {
    const T dr = Scale(term.coefficient, q[term.speed]);
    const T drd = Scale(term.coefficient, qdot[term.speed]);
    switch (term.component) {
      case 0: r0 = Add(r0, dr); d0 = Add(d0, drd); break;
      case 1: r1 = Add(r1, dr); d1 = Add(d1, drd); break;
      default: r2 = Add(r2, dr); d2 = Add(d2, drd); break;
    }
  }
  r[0] = r0;
  r[1] = r1;
  r[2] = r2;
  rd[0] = d0;
  rd[1] = d1;
  rd[2] = d2;
}

// Rᵀ v, inline (the same terms, in the same order, as Eigen's R.transpose() * v).
template <typename T>
inline Vector3<T> TransposeMultiply(const Matrix3<T>& R, const Vector3<T>& v) {
  return Vector3<T>(Dot(R.data(), v.data()), Dot(R.data() + 3, v.data()),
                    Dot(R.data() + 6, v.data()));
}

// I v for a constant inertia matrix (body axes) and a T-vector, with no cast of I to T. A
// diagonal I (principal axes, the common case) skips the terms that are exact zeros.
template <typename T>
inline Vector3<T> InertiaTimes(const Eigen::Matrix3d& I, const Vector3<T>& v) {
  if (I(0, 1) == 0.0 && I(0, 2) == 0.0 && I(1, 2) == 0.0 && I(1, 0) == 0.0 && I(2, 0) == 0.0 &&
      I(2, 1) == 0.0) {
    return Vector3<T>(Scale(I(0, 0), v(0)), Scale(I(1, 1), v(1)), Scale(I(2, 2), v(2)));
  }
  auto row = [&](int a) {
    return Add(Add(Scale(I(a, 0), v(0)), Scale(I(a, 1), v(1))), Scale(I(a, 2), v(2)));
  };
  return Vector3<T>(row(0), row(1), row(2));
}

// Fills data.q_jets from data.q, data.qdot, data.qddot_rem (value-only seeds if `rates` is false).
template <typename T>
void SeedCoordinateJets(Data<T>& data, bool rates);

}  // namespace hybridtest::multibody::internal
