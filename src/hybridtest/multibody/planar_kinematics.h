#pragma once
// Internal to the engine: the kinematics of a planar model (Model::planar_axis() ≥ 0) for
// doubles, with the structural zeros of R, ω and α skipped. See decision 0012.
#include "hybridtest/multibody/data.h"

namespace hybridtest::multibody::internal {

// The frames' and points' kinematics at the state already copied into data (t, q, u, q̇ = u):
// the same values as the general kernels (the terms skipped are exact zeros; only the sign
// of a zero may differ). Writes only the entries that can be non-zero: the others (R's row
// and column of the axis, ω and the partial angular velocities off the axis, α) keep the
// values Data's constructor gave them, which are the planar ones; the partial angular
// velocities, constant, are written once (InitPlanarPartialAngularVelocities). With
// `positions` false the points' positions p_OP and velocities v_NP are left as they were
// (internal::CalcKinematics).
void CalcPlanarKinematics(const Model& model, Data<double>& data, bool positions);

// The partial angular velocities of a planar model: with q̇ = u, ∂ω/∂u_j = w_j e_A where w_j
// sums the constant coefficients of q_j in the angles from N to the frame. Written into
// data.w_partial once, by internal::MakeEvaluationPlan (data.h); CalcPlanarKinematics leaves
// them as they are.
void InitPlanarPartialAngularVelocities(const Model& model, Data<double>& data);

// out = (w_a e_A) × v.
template <int A>
inline void CrossAxis(double w_a, const double* v, double* out) {
  constexpr int B = (A + 1) % 3;
  constexpr int D = (A + 2) % 3;
  out[A] = 0.0;
  out[B] = -(w_a * v[D]);
  out[D] = w_a * v[B];
}

// out = R v for a planar R (column-major), the non-zero terms in the general order.
template <int A>
inline void RotatePlanar(const double* R, const double* v, double* out) {
  constexpr int B = (A + 1) % 3;
  constexpr int D = (A + 2) % 3;
  constexpr int lo = B < D ? B : D;
  constexpr int hi = B < D ? D : B;
  out[A] = v[A];
  out[B] = R[B + 3 * lo] * v[lo] + R[B + 3 * hi] * v[hi];
  out[D] = R[D + 3 * lo] * v[lo] + R[D + 3 * hi] * v[hi];
}

// out = R v for a frame of a planar model about `axis` (R_NF), as RotatePlanar<axis>.
inline void RotatePlanar(int axis, const double* R, const double* v, double* out) {
  switch (axis) {
    case 0: RotatePlanar<0>(R, v, out); break;
    case 1: RotatePlanar<1>(R, v, out); break;
    default: RotatePlanar<2>(R, v, out); break;
  }
}

// data.torque[body.frame] −= I α + ω × I ω (in N) for a body of a planar model about `axis`:
// CalcForcing's inertia torque with the structural zeros skipped. A body whose axis A is
// principal (I e_A = I_AA e_A) has none (its terms would all be exact zeros): checked here,
// inline, as the call alone costs more than the check.
void SubtractPlanarGyroscopicTorque(int axis, const RigidBodySpec& body, Data<double>& data);
inline void SubtractPlanarInertiaTorque(int axis, const RigidBodySpec& body,
                                        Data<double>& data) {
  const int b = axis == 2 ? 0 : axis + 1;  // (axis + 1) % 3 without the division
  const int d = b == 2 ? 0 : b + 1;
  if (body.inertia(b, axis) == 0.0 && body.inertia(d, axis) == 0.0) return;
  SubtractPlanarGyroscopicTorque(axis, body, data);
}

}  // namespace hybridtest::multibody::internal
