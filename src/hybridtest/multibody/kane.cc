// Kane's equations: mass matrix, forcing, state derivative, and exact derivatives through
// AutoDiff. See kane.h for the equations.
#include "hybridtest/multibody/kane.h"

#include <fmt/core.h>

#include <algorithm>
#include <type_traits>

#include "hybridtest/common/error.h"
#include "hybridtest/multibody/constraints.h"
#include "hybridtest/multibody/field_eval.h"
#include "hybridtest/multibody/mass_solve.h"
#include "hybridtest/multibody/planar_kinematics.h"
#include "hybridtest/multibody/tree_mass.h"

namespace hybridtest::multibody {

namespace {

// Out of line: inlined, they change the surrounding loops' code for the worse (measured).
// For doubles and Model::grouped_sums(): the mass terms' sums, entry by entry in a register
// (grouped_mass_terms()): each term's partial sum is stored, the entry's last store holds the
// total; no entry is read back (a chain of stores and loads through memory). An entry's sum
// starts from +0, as M's does in the term-by-term loop.
[[gnu::noinline]] void AddGroupedMassTerms(const Model& model, Data<double>& data) {
  double* m = data.M.data();
  double s = 0.0;
  for (const internal::EvaluationPlan::Mass& term : internal::PlanFor(model, data).mass) {
    const double* vj = term.vj;
    const double* vk = term.vk;
    const double value = term.mass * (vj[0] * vk[0] + vj[1] * vk[1] + vj[2] * vk[2]);
    s = term.continues ? s + value : 0.0 + value;
    m[term.m_jk] = s;
    m[term.m_kj] = s;
  }
}
void AddGroupedMassTerms(const Model&, Data<AutoDiff>&) {}
void AddGroupedMassTerms(const Model&, Data<Symbolic>&) {}

// The generalized forces' sums, speed by speed in a register (projection_terms()).
[[gnu::noinline]] void ProjectGrouped(const Model& model, Data<double>& data) {
  double* g = data.g.data();
  double s = 0.0;
  for (const internal::EvaluationPlan::Projection& term :
       internal::PlanFor(model, data).projection) {
    const double value = internal::Dot(term.partial, term.load);
    s = term.continues ? s + value : 0.0 + value;
    g[term.j] = s;
  }
}
void ProjectGrouped(const Model&, Data<AutoDiff>&) {}
void ProjectGrouped(const Model&, Data<Symbolic>&) {}

}  // namespace

template <typename T>
void CalcMassMatrix(const Model& model, Data<T>& data) {
  if (model.tree_mass_matrix()) {
    internal::CalcTreeMassMatrix(model, data);
  } else {
    CalcMassMatrixPairwise(model, data);
  }
}

template <typename T>
void CalcMassMatrixPairwise(const Model& model, Data<T>& data) {
  MatrixX<T>& M = data.M;
  T* m = M.data();  // column-major: M(j, k) = m[j + k n] (offsets in MassTerm)
  // The constant entries (planar models, constant_mass.h) are copied, not summed; the others
  // start from zero.
  const std::vector<char>& constant = model.constant_mass().entry;
  if (constant.empty()) {
    internal::ZeroN(M.size(), m);
  } else {
    const double* value = model.constant_mass().value.data();
    if constexpr (std::is_same_v<T, double>) {
      internal::CopyN(value, M.size(), m);  // unrolled for n ≤ 4 (a loop costs more)
    } else {
      for (Eigen::Index i = 0; i < M.size(); ++i) m[i] = T(value[i]);
    }
  }
  auto is_constant = [&](int j, int k) {
    return !constant.empty() && constant[static_cast<std::size_t>(j + k * data.n)] != 0;
  };
  if (std::is_same_v<T, double> && model.grouped_sums()) {
    AddGroupedMassTerms(model, data);
  } else {
    // Translational inertia: m v_j·v_k, one precomputed term per pair j ≤ k (both triangles).
    for (const MassTerm& term : model.mass_terms()) {
      if (is_constant(term.j, term.k)) continue;
      const T* v = data.v_partial[term.point].data();
      const T* vj = v + term.vj;
      const T* vk = v + term.vk;
      const T value = term.mass * (vj[0] * vk[0] + vj[1] * vk[1] + vj[2] * vk[2]);
      m[term.m_jk] += value;
      if (term.j != term.k) m[term.m_kj] += value;
    }
  }
  if constexpr (std::is_same_v<T, double>) {
    if (model.planar_axis() >= 0) {
      // Every ω_j is w_j e_A in N and in the body (R's row and column A are e_A), so
      // ω_j·I ω_k = w_k (I_AA w_j), a constant: the general terms below with their exact zeros
      // left out, evaluated once (data.h, EvaluationPlan) and added in the same order.
      for (const internal::EvaluationPlan::Rotation& term :
           internal::PlanFor(model, data).planar_rotation) {
        m[term.m_jk] += term.value;
        if (term.m_kj >= 0) m[term.m_kj] += term.value;
      }
      return;
    }
  }
  for (const RigidBodySpec& body : model.bodies()) {
    const std::vector<int>& active = model.compiled_frames()[body.frame].active;
    // Rotational inertia: ω_j·I ω_k, evaluated in body components (ω_B = Rᵀ ω_N), which
    // avoids forming I_N = R I Rᵀ. The partial angular velocities of the active speeds are
    // rotated once, into the 3 × n scratch.
    const Matrix3<T>& R = data.R_NF[body.frame];
    const Matrix3X<T>& Wp = data.w_partial[body.frame];
    Matrix3X<T>& Wb = data.partial_rate3;
    for (int j : active) Wb.col(j) = internal::TransposeMultiply(R, Vector3<T>(Wp.col(j)));
    for (std::size_t a = 0; a < active.size(); ++a) {
      const Vector3<T> Iw = internal::InertiaTimes(body.inertia, Vector3<T>(Wb.col(active[a])));
      for (std::size_t b = a; b < active.size(); ++b) {
        if (is_constant(active[a], active[b])) continue;
        const T value = Wb.col(active[b]).dot(Iw);
        M(active[a], active[b]) += value;
        if (b != a) M(active[b], active[a]) += value;
      }
    }
  }
}

template <typename T>
void CalcForcing(const Model& model, Data<T>& data, const Eigen::Ref<const VectorX<T>>& r) {
  const int n = data.n;
  const int planar = model.planar_axis();  // doubles skip the planar structural zeros
  if (r.size() != model.num_slots()) {
    throw ModelError(fmt::format("expected {} restoring forces (one per slot), got {}",
                                 model.num_slots(), r.size()));
  }
  internal::CopyN(r.data(), r.size(), data.r.data());  // plain copy: r is contiguous
  for (int p : model.loaded_points()) data.force[p].setZero();
  for (int f : model.loaded_frames()) data.torque[f].setZero();
  // Time functions, once; then the applied loads, converted to N components.
  for (std::size_t k = 0; k < data.time_values.size(); ++k) {
    data.time_values[k] = model.time_functions()[k].function.template get<T>()(data.t);
  }
  const LoadArgs<T> args{data.t, std::span<const T>(data.q.data(), n),
                         std::span<const T>(data.u.data(), n),
                         std::span<const T>(data.r.data(), data.r.size()),
                         std::span<const T>(data.time_values.data(), data.time_values.size()),
                         std::span<const T>(data.z.data(), data.z.size())};
  if constexpr (std::is_same_v<T, double>) {
    // The loads' functions and the addresses of their resultants and rotations, precomputed
    // (data.h, EvaluationPlan).
    for (const internal::EvaluationPlan::Load& load : internal::PlanFor(model, data).loads) {
      const Vector3<double> value = (*load.function)(args);
      double* sum = load.sum;
      if (load.R == nullptr) {
        for (int c = 0; c < 3; ++c) sum[c] = sum[c] + value(c);
      } else if (planar >= 0) {
        // Into a separate array, element by element: a copy of the returned vector is read
        // with one wide load over the callee's narrow stores, which stalls.
        double rotated[3];
        internal::RotatePlanar(planar, load.R->data(), value.data(), rotated);
        for (int c = 0; c < 3; ++c) sum[c] = sum[c] + rotated[c];
      } else {
        const Vector3<double> rotated = internal::Multiply(*load.R, value);
        for (int c = 0; c < 3; ++c) sum[c] = sum[c] + rotated(c);
      }
    }
  } else {
    // The resultants by kind, picked by index (a branch on the kind costs more).
    static_assert(static_cast<int>(LoadSpec::Kind::kForce) == 0 &&
                  static_cast<int>(LoadSpec::Kind::kTorque) == 1);
    Vector3<T>* const sums[2] = {data.force.data(), data.torque.data()};
    for (const LoadSpec& load : model.loads()) {
      const Vector3<T> value = load.function.template get<T>()(args);
      T* sum = sums[static_cast<int>(load.kind)][load.target].data();
      if (load.expressed_in == 0) {
        for (int c = 0; c < 3; ++c) sum[c] = internal::Add(sum[c], value(c));
        continue;
      }
      const Vector3<T> rotated = internal::Multiply(data.R_NF[load.expressed_in], value);
      for (int c = 0; c < 3; ++c) sum[c] = internal::Add(sum[c], rotated(c));
    }
  }
  // Inertia forces and torques (remainder parts: the u̇ parts are in M).
  auto subtract_inertia_force = [&](int point, double mass) {
    T* f = data.force[point].data();
    const T* a = data.a_rem[point].data();
    for (int c = 0; c < 3; ++c) f[c] = internal::Sub(f[c], internal::Scale(mass, a[c]));
  };
  for (const ParticleSpec& p : model.particles()) subtract_inertia_force(p.point, p.mass);
  for (const RigidBodySpec& body : model.bodies()) {
    if (body.mass > 0.0) subtract_inertia_force(body.mass_center, body.mass);
    if constexpr (std::is_same_v<T, double>) {
      if (planar >= 0) {
        internal::SubtractPlanarInertiaTorque(planar, body, data);
        continue;
      }
    }
    // I α + ω × I ω in body components, back to N.
    const Matrix3<T>& R = data.R_NF[body.frame];
    const Vector3<T> w_B = internal::TransposeMultiply(R, data.w_NF[body.frame]);
    const Vector3<T> alpha_B = internal::TransposeMultiply(R, data.alpha_rem[body.frame]);
    const Vector3<T> I_w = internal::InertiaTimes(body.inertia, w_B);
    const Vector3<T> I_alpha = internal::InertiaTimes(body.inertia, alpha_B);
    Vector3<T> gyro;
    internal::Cross(w_B.data(), I_w.data(), gyro.data());
    const Vector3<T> torque = internal::Multiply(R, Vector3<T>(I_alpha + gyro));
    T* sum = data.torque[body.frame].data();
    for (int c = 0; c < 3; ++c) sum[c] = internal::Sub(sum[c], torque(c));
  }
  // Projection onto the partial velocities (Kane's generalized forces).
  T* g = data.g.data();
  internal::ZeroN(n, g);
  if (std::is_same_v<T, double> && model.grouped_sums()) {
    ProjectGrouped(model, data);
    return;
  }
  for (int p : model.loaded_points()) {
    const T* V = data.v_partial[p].data();
    const T* f = data.force[p].data();
    for (int j : model.compiled_points()[p].active)
      g[j] = internal::Add(g[j], internal::Dot(V + 3 * j, f));
  }
  for (int f : model.loaded_frames()) {
    const T* W = data.w_partial[f].data();
    const T* tau = data.torque[f].data();
    for (int j : model.compiled_frames()[f].active)
      g[j] = internal::Add(g[j], internal::Dot(W + 3 * j, tau));
  }
}


namespace {
// A compiled right-hand side (symbolic_compiled.h): M, g, q̇ and ż from the generated code,
// then the engine's own factorisation and solve.
void CalcStateDerivativeCompiled(const Model& model, Data<double>& data, double t,
                                 const Eigen::Ref<const VectorX<double>>& x,
                                 const Eigen::Ref<const VectorX<double>>& r,
                                 Eigen::Ref<VectorX<double>> xdot) {
  const int n = data.n;
  internal::CalcCompiledRhs(model, data, t, x, r);
  if (!internal::FactorMassMatrix(model, data)) {
    throw ModelError(fmt::format("the mass matrix (compiled, {}) is not positive definite at "
                                 "t = {} s", model.compiled_rhs()->path, t));
  }
  internal::SolveFactoredMassMatrix(model, data);
  internal::CopyN(data.qdot.data(), n, xdot.data());
  internal::CopyN(data.udot.data(), n, xdot.data() + n);
  xdot.tail(model.num_extra_states()) = data.zdot;
}
}  // namespace

template <typename T>
void CalcStateDerivative(const Model& model, Data<T>& data, const T& t,
                         const Eigen::Ref<const VectorX<T>>& x,
                         const Eigen::Ref<const VectorX<T>>& r, Eigen::Ref<VectorX<T>> xdot) {
  const int n = data.n;
  if (xdot.size() != model.num_states()) {
    throw ModelError(fmt::format("ẋ has {} entries; expected 2n + nz = {}", xdot.size(),
                                 model.num_states()));
  }
  if (model.has_constraints()) {  // closed loops, rolling: the reduced equations
    CalcConstrainedStateDerivative(model, data, t, x, r, xdot);
    return;
  }
  if constexpr (std::is_same_v<T, double>) {
    if (model.compiled_rhs() != nullptr) {
      CalcStateDerivativeCompiled(model, data, t, x, r, xdot);
      return;
    }
  }
  internal::CalcKinematics(model, data, t, x, model.tree_mass_matrix());
  CalcMassMatrix(model, data);
  // Factored before the forcing, which does not need it: its square roots and divisions
  // overlap with the forcing's work (mass_solve.h).
  if (!internal::FactorMassMatrix(model, data)) {
    throw ModelError(fmt::format("the mass matrix is not positive definite at t = {} s: the "
                                 "generalized coordinates are singular there, or a mass or "
                                 "inertia is missing", ValueOf(t)));
  }
  CalcForcing(model, data, r);
  internal::SolveFactoredMassMatrix(model, data);
  internal::CopyN(data.qdot.data(), n, xdot.data());
  internal::CopyN(data.udot.data(), n, xdot.data() + n);
  // Checked here too: the call alone (and its copy of xdot's Ref) costs more than the check.
  if (model.num_extra_states() > 0) internal::CalcExtraStateRates(model, data, xdot);
}

namespace internal {
void CalcCompiledRhs(const Model& model, Data<double>& data, double t,
                     const Eigen::Ref<const VectorX<double>>& x,
                     const Eigen::Ref<const VectorX<double>>& r) {
  const int n = data.n;
  const CompiledRhs& compiled = *model.compiled_rhs();
  data.t = t;
  data.q = x.head(n);
  data.u = x.segment(n, n);
  data.z = x.tail(model.num_extra_states());
  data.r = r;
  compiled.function(t, x.data(), r.data(), data.M.data(), data.g.data(), data.qdot.data(),
                    data.zdot.data());
  if (!model.has_constraints()) return;
  if (compiled.constraints == nullptr) {
    throw ModelError(fmt::format("the compiled model {} has no constraint rows, the model has "
                                 "{}: it was compiled for another model; compile it again",
                                 compiled.path, model.num_constraint_rows()));
  }
  compiled.constraints(t, x.data(), data.constraint_B.data(), data.constraint_velocity.data(),
                       data.constraint_position.data(), data.constraint_bias.data());
}

template <typename T>
void CalcExtraStateRates(const Model& model, Data<T>& data, Eigen::Ref<VectorX<T>> xdot) {
  if (model.num_extra_states() == 0) return;
  // ż = f_z(t, q, u, z): the loads' inputs with r left out.
  const int n = data.n;
  const LoadArgs<T> args{data.t, std::span<const T>(data.q.data(), n),
                         std::span<const T>(data.u.data(), n), std::span<const T>(),
                         std::span<const T>(data.time_values.data(), data.time_values.size()),
                         std::span<const T>(data.z.data(), data.z.size())};
  for (int k = 0; k < model.num_extra_states(); ++k) {
    data.zdot(k) = model.extra_states()[k].rate.template get<T>()(args);
  }
  xdot.tail(model.num_extra_states()) = data.zdot;
}
template void CalcExtraStateRates<double>(const Model&, Data<double>&, Eigen::Ref<VectorX<double>>);
template void CalcExtraStateRates<AutoDiff>(const Model&, Data<AutoDiff>&,
                                            Eigen::Ref<VectorX<AutoDiff>>);
}  // namespace internal

#define HYBRIDTEST_INSTANTIATE(T)                                                             \
  template void CalcMassMatrix<T>(const Model&, Data<T>&);                                    \
  template void CalcMassMatrixPairwise<T>(const Model&, Data<T>&);                            \
  template void CalcForcing<T>(const Model&, Data<T>&, const Eigen::Ref<const VectorX<T>>&);  \
  template void CalcStateDerivative<T>(const Model&, Data<T>&, const T&,                      \
                                       const Eigen::Ref<const VectorX<T>>&,                   \
                                       const Eigen::Ref<const VectorX<T>>&,                   \
                                       Eigen::Ref<VectorX<T>>);
HYBRIDTEST_INSTANTIATE(double)
HYBRIDTEST_INSTANTIATE(AutoDiff)
#undef HYBRIDTEST_INSTANTIATE
// Symbolic (printing, decision 0019): the general paths only; no factorisation or solve.
template void CalcMassMatrixPairwise<Symbolic>(const Model&, Data<Symbolic>&);
template void CalcForcing<Symbolic>(const Model&, Data<Symbolic>&,
                                    const Eigen::Ref<const VectorX<Symbolic>>&);

}  // namespace hybridtest::multibody
