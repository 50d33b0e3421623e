// Kinematics of planar models for doubles. See planar_kinematics.h.
//
// Every frame turns about the same coordinate axis A of N, so with (A, B, D) cyclic,
// R_NF = [1 0 0; 0 c −s; 0 s c] in the order (A, B, D), ω = ω_A e_A, every partial angular
// velocity is along e_A and α_rem = α_P + ω_P × ω_rel = 0. The point kernel is the general
// affine one (kinematics.cc) with ρ = R r over the two non-zero columns of each row and
// (ω_A e_A) × v = ω_A (v_B e_D − v_D e_B). Sums keep the general kernels' order of terms, so
// the values are theirs up to the sign of a zero.
#include "hybridtest/multibody/planar_kinematics.h"

#include <cmath>

#include "hybridtest/multibody/field_eval.h"

namespace hybridtest::multibody::internal {
namespace {

// R_NF and ω of frame i. Its partial angular velocities are constant (q̇ = u): written once,
// by InitPlanarPartialAngularVelocities.
template <int A>
void PlanarFrame(const Model& model, Data<double>& data, int i) {
  constexpr int B = (A + 1) % 3;
  constexpr int D = (A + 2) % 3;
  const FrameSpec& spec = model.frames()[i];
  const CompiledFrame& f = model.compiled_frames()[i];
  const int p = spec.parent;
  double c, s;
  const double w_p = data.w_NF[p](A);
  if (f.constant_rotation) {
    c = f.constant_cos;
    s = f.constant_sin;
    data.w_NF[i](A) = w_p;
  } else {
    const ScalarField& field = spec.angle;
    double angle = field.constant();
    double rate = field.time_rate();
    if (field.time_rate() != 0.0) angle += field.time_rate() * data.t;
    for (const auto& term : field.terms()) {
      angle += term.coefficient * data.q(term.coordinate);
      rate += term.coefficient * data.qdot(term.coordinate);
    }
    c = std::cos(angle);
    s = std::sin(angle);
    data.w_NF[i](A) = w_p + rate;  // the axis in N is e_A exactly
  }
  const Matrix3<double>& R_NP = data.R_NF[p];
  Matrix3<double>& R_NF = data.R_NF[i];
  for (int r : {B, D}) {
    const double b = R_NP(r, B);
    const double d = R_NP(r, D);
    R_NF(r, B) = c * b + s * d;
    R_NF(r, D) = c * d - s * b;
  }
}

// kPositions: also p_OP and v_NP (the right-hand side needs neither; planar_kinematics.h).
template <int A, bool kPositions>
void PlanarPoint(const Model& model, Data<double>& data, int i) {
  constexpr int B = (A + 1) % 3;
  constexpr int D = (A + 2) % 3;
  const PointSpec& spec = model.points()[i];
  const CompiledPoint& pt = model.compiled_points()[i];
  const int o = spec.from;
  const int e = spec.frame;
  double r[3], rd[3];
  AffinePointOffset(pt, data.t, data.q.data(), data.qdot.data(), r, rd);
  const double* R = data.R_NF[e].data();
  const double w = data.w_NF[e](A);
  double rho[3], rho_rel_dot[3], w_rho[3];
  RotatePlanar<A>(R, r, rho);
  RotatePlanar<A>(R, rd, rho_rel_dot);
  CrossAxis<A>(w, rho, w_rho);
  if constexpr (kPositions) {
    const double* p_o = data.p_OP[o].data();
    const double* v_o = data.v_NP[o].data();
    double* p_i = data.p_OP[i].data();
    double* v_i = data.v_NP[i].data();
    for (int c = 0; c < 3; ++c) {
      p_i[c] = p_o[c] + rho[c];
      v_i[c] = (v_o[c] + w_rho[c]) + rho_rel_dot[c];
    }
  }
  double* V = data.v_partial[i].data();
  const double* V_o = data.v_partial[o].data();
  const double* W_e = data.w_partial[e].data();
  for (int j : pt.from_only) Copy3(V_o + 3 * j, V + 3 * j);
  for (int j : pt.frame_only) CrossAxis<A>(W_e[3 * j + A], rho, V + 3 * j);
  for (int j : pt.from_and_frame) {
    double wj_rho[3];
    CrossAxis<A>(W_e[3 * j + A], rho, wj_rho);
    for (int c = 0; c < 3; ++c) V[3 * j + c] = V_o[3 * j + c] + wj_rho[c];
  }
  for (int j : pt.fresh) V[3 * j] = V[3 * j + 1] = V[3 * j + 2] = 0.0;
  for (const auto& term : pt.rate_terms) {
    double* col = V + 3 * term.speed;
    const double* axis = R + 3 * term.component;
    // Off the axis, axis[A] = R(A, component) is +0 (never written) and col[A] is never −0
    // (the kernels above write +0 there, or copy or add to such a value): col[A] + c·(±0) is
    // col[A], left out.
    if (term.component != A) {
      col[B] = col[B] + term.coefficient * axis[B];
      col[D] = col[D] + term.coefficient * axis[D];
      continue;
    }
    for (int c = 0; c < 3; ++c) col[c] = col[c] + term.coefficient * axis[c];
  }
  double w_w_rho[3], w_rho_dot[3];
  CrossAxis<A>(w, w_rho, w_w_rho);
  CrossAxis<A>(w, rho_rel_dot, w_rho_dot);
  const double* a_o = data.a_rem[o].data();
  double* a_i = data.a_rem[i].data();
  for (int c = 0; c < 3; ++c) a_i[c] = (a_o[c] + w_w_rho[c]) + 2.0 * w_rho_dot[c];
}

template <int A>
void PlanarKinematics(const Model& model, Data<double>& data, bool positions) {
  const int nf = static_cast<int>(model.frames().size());
  const int np = static_cast<int>(model.points().size());
  for (int i = 1; i < nf; ++i) PlanarFrame<A>(model, data, i);
  if (positions) {
    for (int i = 1; i < np; ++i) PlanarPoint<A, true>(model, data, i);
  } else {
    for (int i = 1; i < np; ++i) PlanarPoint<A, false>(model, data, i);
  }
}

}  // namespace

void SubtractPlanarGyroscopicTorque(int axis, const RigidBodySpec& body, Data<double>& data) {
  // ω_B = Rᵀ ω = ω_A e_A (R's row A is e_A), α_rem = 0: I α = 0, and the gyroscopic torque
  // ω_B × I ω_B with I ω_B = ω_A I e_A; back to N through R.
  const double w = data.w_NF[body.frame](axis);
  const double Iw[3] = {body.inertia(0, axis) * w, body.inertia(1, axis) * w,
                        body.inertia(2, axis) * w};
  double gyro[3], torque[3];
  switch (axis) {
    case 0: CrossAxis<0>(w, Iw, gyro); break;
    case 1: CrossAxis<1>(w, Iw, gyro); break;
    default: CrossAxis<2>(w, Iw, gyro); break;
  }
  RotatePlanar(axis, data.R_NF[body.frame].data(), gyro, torque);
  double* sum = data.torque[body.frame].data();
  for (int c = 0; c < 3; ++c) sum[c] = sum[c] - torque[c];
}

void InitPlanarPartialAngularVelocities(const Model& model, Data<double>& data) {
  const int A = model.planar_axis();
  for (std::size_t i = 1; i < model.frames().size(); ++i) {
    const CompiledFrame& f = model.compiled_frames()[i];
    const auto p = static_cast<std::size_t>(model.frames()[i].parent);
    double* Wi = data.w_partial[i].data();
    const double* Wp = data.w_partial[p].data();
    if (f.constant_rotation) {
      for (int j : f.active) Wi[3 * j + A] = Wp[3 * j + A];
      continue;
    }
    for (int j : model.compiled_frames()[p].active) Wi[3 * j + A] = Wp[3 * j + A];
    for (int j : f.fresh) Wi[3 * j + A] = 0.0;
    for (const auto& term : model.frames()[i].angle.terms())
      Wi[3 * term.coordinate + A] += term.coefficient;
  }
}

void CalcPlanarKinematics(const Model& model, Data<double>& data, bool positions) {
  PlanFor(model, data);  // a copied Data, or another model: the constant ∂ω/∂u first
  switch (model.planar_axis()) {
    case 0: PlanarKinematics<0>(model, data, positions); break;
    case 1: PlanarKinematics<1>(model, data, positions); break;
    default: PlanarKinematics<2>(model, data, positions); break;
  }
}

}  // namespace hybridtest::multibody::internal
