// Kinematics of the frame and point trees: CalcKinematics and CalcSlotDisplacements. See
// kane.h for the equations.
#include <fmt/core.h>

#include <algorithm>
#include <type_traits>

#include "hybridtest/common/error.h"
#include "hybridtest/multibody/field_eval.h"
#include "hybridtest/multibody/kane.h"
#include "hybridtest/multibody/planar_kinematics.h"

namespace hybridtest::multibody {

using internal::EvalField;
using internal::FieldEval;


namespace {

template <typename T>
Vector3<T> Vee(const Matrix3<T>& S) {  // axial vector of the skew part of S
  return Vector3<T>(0.5 * (S(2, 1) - S(1, 2)), 0.5 * (S(0, 2) - S(2, 0)),
                    0.5 * (S(1, 0) - S(0, 1)));
}

// q̇ = W u and q̈_rem = Ẇ u for a model with a user kinematical matrix W(q).
template <typename T>
void CalcKinematicalEquations(const Model& model, Data<T>& data) {
  const int n = data.n;
  std::span<Jet<T>> w(data.jet_buffer.data(), std::size_t(n) * n);
  Jet<T> time;
  time.v = data.t;
  time.d1 = T(1.0);
  // First pass: W(q) (values only) gives q̇.
  internal::SeedCoordinateJets(data, false);
  const KinematicArgs<T> args{std::span<const Jet<T>>(data.q_jets.data(), n), time};
  model.kinematic_matrix().template get<T>()(args, w);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) data.W(i, j) = w[std::size_t(i) * n + j].v;
  data.qdot.noalias() = data.W * data.u;
  // Second pass, along q̇: Ẇ gives q̈ with u̇ = 0.
  data.qddot_rem.setZero();
  internal::SeedCoordinateJets(data, true);
  model.kinematic_matrix().template get<T>()(args, w);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) data.qddot_rem(i) += w[std::size_t(i) * n + j].d1 * data.u(j);
}

// R_NF = R_NP · R_PF for a rotation about the parent's unit vector e_A by the angle with
// cosine c and sine s: column A is kept, the other two rotate in their plane (no 3 × 3 product).
template <int A, typename T>
[[gnu::always_inline]] inline void RotateAboutParentAxis(const Matrix3<T>& R_NP, const T& c,
                                                         const T& s, Matrix3<T>& R_NF) {
  constexpr int kB = (A + 1) % 3;
  constexpr int kD = (A + 2) % 3;
  // Scalar code: Eigen leaves these 3-element column expressions to out-of-line loops.
  for (int r = 0; r < 3; ++r) {
    const T b = R_NP(r, kB);
    const T d = R_NP(r, kD);
    R_NF(r, A) = R_NP(r, A);
    R_NF(r, kB) = internal::Add(internal::Mul(c, b), internal::Mul(s, d));
    R_NF(r, kD) = internal::Sub(internal::Mul(c, d), internal::Mul(s, b));
  }
}

// Inlined at every call site: an out-of-line call through the switch costs as much as the
// rotation itself.
template <typename T>
[[gnu::always_inline]] inline void RotateAboutParentAxis(const Matrix3<T>& R_NP, int a,
                                                         const T& c, const T& s,
                                                         Matrix3<T>& R_NF) {
  switch (a) {
    case 0: RotateAboutParentAxis<0>(R_NP, c, s, R_NF); break;
    case 1: RotateAboutParentAxis<1>(R_NP, c, s, R_NF); break;
    default: RotateAboutParentAxis<2>(R_NP, c, s, R_NF); break;
  }
}

template <typename T>
void CalcAffineAngleFrame(const Model& model, const FrameSpec& spec, const CompiledFrame& f,
                          Data<T>& data, int i) {
  using std::cos;
  using std::sin;
  const int p = spec.parent;
  const ScalarField& field = spec.angle;
  T angle = T(field.constant());
  T rate = T(field.time_rate());
  if (field.time_rate() != 0.0) angle += field.time_rate() * data.t;
  for (const auto& term : field.terms()) {
    angle += term.coefficient * data.q(term.coordinate);
    rate += term.coefficient * data.qdot(term.coordinate);
  }
  const Matrix3<T>& R_NP = data.R_NF[p];
  Vector3<T> axis_N;
  if (f.axis_index >= 0) {
    internal::Copy3(R_NP.data() + 3 * f.axis_index, axis_N.data());
    RotateAboutParentAxis(R_NP, f.axis_index, T(cos(angle)), T(sin(angle)), data.R_NF[i]);
  } else {
    axis_N = R_NP * f.axis.template cast<T>();
    data.R_NF[i] = R_NP * internal::RotationAboutAxis(f.axis, angle);
  }
  const T* a = axis_N.data();
  const T w_rel[3] = {internal::Mul(rate, a[0]), internal::Mul(rate, a[1]),
                      internal::Mul(rate, a[2])};
  const T* w_p = data.w_NF[p].data();
  T* w_i = data.w_NF[i].data();
  for (int c = 0; c < 3; ++c) w_i[c] = internal::Add(w_p[c], w_rel[c]);
  T* Wi = data.w_partial[i].data();
  const T* Wp = data.w_partial[p].data();
  for (int j : model.compiled_frames()[p].active) internal::Copy3(Wp + 3 * j, Wi + 3 * j);
  for (int j : f.fresh) Wi[3 * j] = Wi[3 * j + 1] = Wi[3 * j + 2] = T(0.0);
  for (const auto& term : field.terms()) {
    T* col = Wi + 3 * term.coordinate;
    for (int c = 0; c < 3; ++c)
      col[c] = internal::Add(col[c], internal::Scale(term.coefficient, a[c]));
  }
  T wxw[3];
  internal::Cross(w_p, w_rel, wxw);
  const T* alpha_p = data.alpha_rem[p].data();
  T* alpha_i = data.alpha_rem[i].data();
  for (int c = 0; c < 3; ++c) alpha_i[c] = internal::Add(alpha_p[c], wxw[c]);
}

template <typename T>
void CalcFrame(const Model& model, Data<T>& data, int i) {
  const FrameSpec& spec = model.frames()[i];
  const CompiledFrame& f = model.compiled_frames()[i];
  const int p = spec.parent;
  const Matrix3<T>& R_NP = data.R_NF[p];
  if (spec.kind == FrameSpec::Kind::kAxisAngle) {
    if (f.constant_rotation) {
      if (f.axis_index >= 0) {
        RotateAboutParentAxis(R_NP, f.axis_index, T(f.constant_cos), T(f.constant_sin),
                              data.R_NF[i]);
      } else {
        data.R_NF[i] = R_NP * f.constant_R_PF.template cast<T>();
      }
      internal::Copy3(data.w_NF[p].data(), data.w_NF[i].data());
      T* Wi = data.w_partial[i].data();
      const T* Wp = data.w_partial[p].data();
      for (int j : f.active) internal::Copy3(Wp + 3 * j, Wi + 3 * j);
      internal::Copy3(data.alpha_rem[p].data(), data.alpha_rem[i].data());
      return;
    }
    if (f.affine_angle) {
      CalcAffineAngleFrame(model, spec, f, data, i);
      return;
    }
    T* rate = data.partial_rate.data();
    const FieldEval<T> angle = EvalField(model, data, spec.angle, rate);
    Vector3<T> axis_N;
    if (f.axis_index >= 0) {
      using std::cos;
      using std::sin;
      axis_N = R_NP.col(f.axis_index);
      RotateAboutParentAxis(R_NP, f.axis_index, T(cos(angle.v)), T(sin(angle.v)), data.R_NF[i]);
    } else {
      axis_N = R_NP * f.axis.template cast<T>();
      data.R_NF[i] = R_NP * internal::RotationAboutAxis(f.axis, angle.v);
    }
    const Vector3<T> w_rel = angle.d1 * axis_N;
    data.w_NF[i] = data.w_NF[p] + w_rel;
    for (int j : f.active) data.w_partial[i].col(j) = data.w_partial[p].col(j) + rate[j] * axis_N;
    data.alpha_rem[i] = data.alpha_rem[p] + angle.d2 * axis_N + data.w_NF[p].cross(w_rel);
    return;
  }
  // General direction-cosine matrix C = R_PF(q, t): ω_rel = vee(Ċ Cᵀ), α_rel = vee(C̈ Cᵀ).
  const int n = data.n;
  std::span<Jet<T>> c(data.jet_buffer.data(), 9);
  Jet<T> time;
  time.v = data.t;
  time.d1 = T(1.0);
  const KinematicArgs<T> args{std::span<const Jet<T>>(data.q_jets.data(), n), time};
  spec.dcm.template get<T>()(args, c);
  Matrix3<T> C, Cd, Cdd;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      C(a, b) = c[a * 3 + b].v;
      Cd(a, b) = c[a * 3 + b].d1;
      Cdd(a, b) = c[a * 3 + b].d2;
    }
  data.R_NF[i] = R_NP * C;
  const Vector3<T> w_rel = R_NP * Vee<T>(Cd * C.transpose());
  data.w_NF[i] = data.w_NF[p] + w_rel;
  for (int j : f.active) {
    Matrix3<T> dC = Matrix3<T>::Zero();  // ∂Ċ/∂u_j = Σ_k ∂C/∂q_k W_kj
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        const Jet<T>& e = c[a * 3 + b];
        for (int k = 0; k < e.n; ++k) {
          dC(a, b) += model.has_identity_kinematics() ? (k == j ? e.dq[k] : T(0.0))
                                                      : T(e.dq[k] * data.W(k, j));
        }
      }
    data.w_partial[i].col(j) = data.w_partial[p].col(j) + R_NP * Vee<T>(dC * C.transpose());
  }
  data.alpha_rem[i] =
      data.alpha_rem[p] + R_NP * Vee<T>(Cdd * C.transpose()) + data.w_NF[p].cross(w_rel);
}

// A point whose position components are all affine, with q̇ = u (CompiledPoint::affine): the
// partial rates are constants, added column by column (R_NE e_c c_k) with no scratch.
// With `positions` false, p_OP and v_NP are skipped (internal::CalcKinematics).
template <typename T>
void CalcAffinePoint(const PointSpec& spec, const CompiledPoint& pt, Data<T>& data, int i,
                     bool positions) {
  using internal::Add;
  using internal::Cross;
  using internal::Mul;
  using internal::Scale;
  const int o = spec.from;
  const int e = spec.frame;
  T r[3], rd[3];
  internal::AffinePointOffset(pt, data.t, data.q.data(), data.qdot.data(), r, rd);
  const T* R = data.R_NF[e].data();  // column-major: R(a, b) = R[a + 3 b]
  const T* w = data.w_NF[e].data();
  T rho[3], rho_rel_dot[3];  // ρ, and its rate as seen in E (N components)
  for (int c = 0; c < 3; ++c) {
    rho[c] = Add(Add(Mul(R[c], r[0]), Mul(R[c + 3], r[1])), Mul(R[c + 6], r[2]));
    rho_rel_dot[c] = Add(Add(Mul(R[c], rd[0]), Mul(R[c + 3], rd[1])), Mul(R[c + 6], rd[2]));
  }
  T w_rho[3];
  Cross(w, rho, w_rho);
  if (positions) {
    const T* p_o = data.p_OP[o].data();
    const T* v_o = data.v_NP[o].data();
    T* p_i = data.p_OP[i].data();
    T* v_i = data.v_NP[i].data();
    for (int c = 0; c < 3; ++c) {
      p_i[c] = Add(p_o[c], rho[c]);
      v_i[c] = Add(Add(v_o[c], w_rho[c]), rho_rel_dot[c]);
    }
  }
  // Columns: from's and/or ω_j × ρ (or zero), then the constant rates.
  T* V = data.v_partial[i].data();
  const T* V_o = data.v_partial[o].data();
  const T* W_e = data.w_partial[e].data();
  for (int j : pt.from_only) internal::Copy3(V_o + 3 * j, V + 3 * j);
  for (int j : pt.frame_only) Cross(W_e + 3 * j, rho, V + 3 * j);
  for (int j : pt.from_and_frame) {
    T wj_rho[3];
    Cross(W_e + 3 * j, rho, wj_rho);
    for (int c = 0; c < 3; ++c) V[3 * j + c] = Add(V_o[3 * j + c], wj_rho[c]);
  }
  for (int j : pt.fresh) V[3 * j] = V[3 * j + 1] = V[3 * j + 2] = T(0.0);
  for (const auto& term : pt.rate_terms) {
    T* col = V + 3 * term.speed;
    const T* axis = R + 3 * term.component;
    for (int c = 0; c < 3; ++c) col[c] = Add(col[c], Scale(term.coefficient, axis[c]));
  }
  T alpha_rho[3], w_w_rho[3], w_rho_dot[3];
  Cross(data.alpha_rem[e].data(), rho, alpha_rho);
  Cross(w, w_rho, w_w_rho);
  Cross(w, rho_rel_dot, w_rho_dot);
  const T* a_o = data.a_rem[o].data();
  T* a_i = data.a_rem[i].data();
  for (int c = 0; c < 3; ++c)
    a_i[c] = Add(Add(Add(a_o[c], alpha_rho[c]), w_w_rho[c]), Scale(2.0, w_rho_dot[c]));
}

template <typename T>
void CalcPoint(const Model& model, Data<T>& data, int i, bool positions) {
  const PointSpec& spec = model.points()[i];
  const CompiledPoint& pt = model.compiled_points()[i];
  if (pt.affine) {
    CalcAffinePoint(spec, pt, data, i, positions);
    return;
  }
  const int o = spec.from;
  const int e = spec.frame;
  Vector3<T> r, rd, rdd;
  Matrix3X<T>& rate = data.partial_rate3;
  bool has_rdd = false;  // r̈_rem ≠ 0 is possible (a general field or a kinematical matrix)
  for (int c = 0; c < 3; ++c) {
    const ScalarField& field = spec.position[c];
    if (field.is_constant()) {
      r(c) = T(field.constant());
      rd(c) = T(0.0);
      rdd(c) = T(0.0);
      for (int j : pt.active) rate(c, j) = T(0.0);
      continue;
    }
    if (field.is_affine() && model.has_identity_kinematics()) {
      // The common case, inline (same operations as EvalField): φ = c0 + c_t t + Σ c_k q_k,
      // φ̇ = c_t + Σ c_k u_k, φ̈_rem = 0, ∂φ̇/∂u_k = c_k, written straight into the rates.
      T v = T(field.constant()) + field.time_rate() * data.t;
      T d1 = T(field.time_rate());
      for (int j : pt.active) rate(c, j) = T(0.0);
      for (const auto& term : field.terms()) {
        v += term.coefficient * data.q(term.coordinate);
        d1 += term.coefficient * data.qdot(term.coordinate);
        rate(c, term.coordinate) += T(term.coefficient);
      }
      r(c) = v;
      rd(c) = d1;
      rdd(c) = T(0.0);
      continue;
    }
    has_rdd = true;
    const FieldEval<T> ev = EvalField(model, data, field, data.partial_rate.data());
    r(c) = ev.v;
    rd(c) = ev.d1;
    rdd(c) = ev.d2;
    for (int j : pt.active) rate(c, j) = data.partial_rate(j);
  }
  const Matrix3<T>& R_NE = data.R_NF[e];
  const Vector3<T>& w = data.w_NF[e];
  const Vector3<T> rho = R_NE * r;
  const Vector3<T> rho_rel_dot = R_NE * rd;  // rate of rho as seen in E, N components
  data.p_OP[i] = data.p_OP[o] + rho;
  data.v_NP[i] = data.v_NP[o] + w.cross(rho) + rho_rel_dot;
  for (int j : pt.active) {
    data.v_partial[i].col(j) = data.v_partial[o].col(j) +
                               Vector3<T>(data.w_partial[e].col(j)).cross(rho) +
                               R_NE * rate.col(j);
  }
  data.a_rem[i] = data.a_rem[o] + data.alpha_rem[e].cross(rho) + w.cross(w.cross(rho)) +
                  2.0 * w.cross(rho_rel_dot);
  if (has_rdd) data.a_rem[i] += R_NE * rdd;
}

}  // namespace

template <typename T>
void CalcKinematics(const Model& model, Data<T>& data, const T& t,
                    const Eigen::Ref<const VectorX<T>>& x) {
  internal::CalcKinematics(model, data, t, x, true);
}

namespace internal {
template <typename T>
void CalcKinematics(const Model& model, Data<T>& data, const T& t,
                    const Eigen::Ref<const VectorX<T>>& x, bool positions) {
  const int n = data.n;
  if (x.size() != model.num_states()) {
    throw ModelError(fmt::format("state vector has {} entries; the model needs x = [q; u; z] "
                                 "with 2n + nz = {}", x.size(), model.num_states()));
  }
  data.t = t;
  // Plain copies (x is contiguous): Eigen's dynamic-size assignment is an out-of-line loop.
  const T* xs = x.data();
  internal::CopyN(xs, n, data.q.data());
  internal::CopyN(xs + n, n, data.u.data());
  if (model.num_extra_states() > 0) {
    std::copy_n(xs + 2 * n, model.num_extra_states(), data.z.data());
  }
  if (model.has_identity_kinematics()) {
    internal::CopyN(xs + n, n, data.qdot.data());
  } else {
    CalcKinematicalEquations(model, data);
  }
  if constexpr (std::is_same_v<T, double>) {
    if (model.planar_axis() >= 0) {
      CalcPlanarKinematics(model, data, positions);
      return;
    }
  }
  if (model.has_general_fields()) SeedCoordinateJets(data, true);
  const int nf = static_cast<int>(model.frames().size());
  const int np = static_cast<int>(model.points().size());
  for (int i = 1; i < nf; ++i) CalcFrame(model, data, i);
  for (int i = 1; i < np; ++i) CalcPoint(model, data, i, positions);
}
}  // namespace internal

template <typename T>
void CalcSlotDisplacements(const Model& model, Data<T>& data, const T& t,
                           const Eigen::Ref<const VectorX<T>>& q, Eigen::Ref<VectorX<T>> d) {
  if (q.size() != data.n || d.size() != model.num_slots()) {
    throw ModelError(fmt::format("CalcSlotDisplacements: expected q of size {} and d of size {}, "
                                 "got {} and {}", data.n, model.num_slots(), q.size(), d.size()));
  }
  data.t = t;
  data.q = q;
  data.qdot.setZero();
  data.qddot_rem.setZero();
  if (model.has_general_fields()) internal::SeedCoordinateJets(data, false);
  for (int s = 0; s < model.num_slots(); ++s) {
    d(s) = EvalField(model, data, model.slots()[s].displacement, static_cast<T*>(nullptr)).v;
  }
}

#define HYBRIDTEST_INSTANTIATE(T)                                                           \
  template void CalcKinematics<T>(const Model&, Data<T>&, const T&,                         \
                                  const Eigen::Ref<const VectorX<T>>&);                     \
  template void internal::CalcKinematics<T>(const Model&, Data<T>&, const T&,               \
                                            const Eigen::Ref<const VectorX<T>>&, bool);     \
  template void CalcSlotDisplacements<T>(const Model&, Data<T>&, const T&,                  \
                                         const Eigen::Ref<const VectorX<T>>&,               \
                                         Eigen::Ref<VectorX<T>>);
HYBRIDTEST_INSTANTIATE(double)
HYBRIDTEST_INSTANTIATE(AutoDiff)
HYBRIDTEST_INSTANTIATE(Symbolic)
#undef HYBRIDTEST_INSTANTIATE

}  // namespace hybridtest::multibody
