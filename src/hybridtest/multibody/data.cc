// The Data<T> constructor: every workspace sized once. See data.h.
#include "hybridtest/multibody/data.h"

#include <algorithm>
#include <type_traits>

#include "hybridtest/multibody/planar_kinematics.h"

namespace hybridtest::multibody {

namespace {
// The columns of M's factor that follow from constant entries of M alone (constant_mass.h),
// which the factorisation of doubles skips (mass_solve.cc): L(i, j) at [i n + j], and 1/L_jj.
template <typename T>
void WriteConstantFactorColumns(const Model& model, Data<T>& data) {
  const ConstantMassPlan& constant = model.constant_mass();
  const int n = data.n;
  for (int j = 0; j < static_cast<int>(constant.factor_column.size()); ++j) {
    if (!constant.factor_column[static_cast<std::size_t>(j)]) continue;
    data.factor_inv_diag(j) = T(constant.factor_inv_diag[static_cast<std::size_t>(j)]);
    for (int i = j + 1; i < n; ++i) {
      const std::size_t at = static_cast<std::size_t>(i) * n + j;
      data.cholesky_factor.data()[at] = T(constant.factor[at]);
    }
  }
}
}  // namespace

namespace internal {
void MakeEvaluationPlan(const Model& model, Data<double>& data) {
  EvaluationPlan& plan = data.plan;
  plan.owner = &data;
  plan.model_id = model.instance_id();
  plan.mass.clear();
  plan.projection.clear();
  plan.loads.clear();
  plan.planar_rotation.clear();
  WriteConstantFactorColumns(model, data);  // again: `data` may have served another model
  for (const LoadSpec& load : model.loads()) {
    const auto target = static_cast<std::size_t>(load.target);
    double* sum = load.kind == LoadSpec::Kind::kForce ? data.force[target].data()
                                                      : data.torque[target].data();
    const Matrix3<double>* R =
        load.expressed_in == 0 ? nullptr
                               : &data.R_NF[static_cast<std::size_t>(load.expressed_in)];
    plan.loads.push_back({&load.function.get<double>(), sum, R});
  }
  if (model.grouped_sums()) {
    for (const MassTerm& term : model.grouped_mass_terms()) {
      const double* v = data.v_partial[static_cast<std::size_t>(term.point)].data();
      plan.mass.push_back(
          {v + term.vj, v + term.vk, term.mass, term.m_jk, term.m_kj, term.continues});
    }
    for (const ProjectionTerm& term : model.projection_terms()) {
      const auto index = static_cast<std::size_t>(term.index);
      const double* partial =
          term.frame ? data.w_partial[index].data() : data.v_partial[index].data();
      const double* load = term.frame ? data.torque[index].data() : data.force[index].data();
      plan.projection.push_back({partial + 3 * term.j, load, term.j, term.continues});
    }
  }
  const int axis = model.planar_axis();
  if (axis < 0) return;
  InitPlanarPartialAngularVelocities(model, data);
  // The bodies' rotational terms of M, in the order (and with the operations) of the general
  // loop: ω_j·I ω_k = w_k (I_AA w_j) with every ω_j = w_j e_A.
  const int n = data.n;
  const std::vector<char>& constant = model.constant_mass().entry;
  for (const RigidBodySpec& body : model.bodies()) {
    const std::vector<int>& active = model.compiled_frames()[body.frame].active;
    const double* W = data.w_partial[static_cast<std::size_t>(body.frame)].data();
    const double I_AA = body.inertia(axis, axis);
    for (std::size_t a = 0; a < active.size(); ++a) {
      const double Iw = I_AA * W[3 * active[a] + axis];
      for (std::size_t b = a; b < active.size(); ++b) {
        const int m_ab = active[a] + active[b] * n;
        if (!constant.empty() && constant[static_cast<std::size_t>(m_ab)]) continue;
        plan.planar_rotation.push_back(
            {m_ab, b != a ? active[b] + active[a] * n : -1, W[3 * active[b] + axis] * Iw});
      }
    }
  }
}
}  // namespace internal

template <typename T>
Data<T>::Data(const Model& model) : n(model.num_coordinates()) {
  const std::size_t nf = model.frames().size();
  const std::size_t np = model.points().size();
  q.setZero(n);
  u.setZero(n);
  z.setZero(model.num_extra_states());
  zdot.setZero(model.num_extra_states());
  qdot.setZero(n);
  qddot_rem.setZero(n);
  W = MatrixX<T>::Identity(n, n);
  R_NF.assign(nf, Matrix3<T>::Identity());
  w_NF.assign(nf, Vector3<T>::Zero());
  w_partial.assign(nf, Matrix3X<T>::Zero(3, n));
  alpha_rem.assign(nf, Vector3<T>::Zero());
  p_OP.assign(np, Vector3<T>::Zero());
  v_NP.assign(np, Vector3<T>::Zero());
  v_partial.assign(np, Matrix3X<T>::Zero(3, n));
  a_rem.assign(np, Vector3<T>::Zero());
  M.setZero(n, n);
  g.setZero(n);
  udot.setZero(n);
  r.setZero(model.num_slots());
  time_values.assign(model.time_functions().size(), T(0.0));
  force.assign(np, Vector3<T>::Zero());
  torque.assign(nf, Vector3<T>::Zero());
  // Jets only for general fields, W(q) or DCM frames (a Jet<AutoDiff> is kilobytes).
  if (model.has_general_fields()) {
    q_jets.assign(n, Jet<T>());
    jet_buffer.assign(std::max<std::size_t>(9, std::size_t(n) * n), Jet<T>());
  }
  partial_rate.setZero(n);
  partial_rate3.setZero(3, n);
  cholesky_factor.setZero(n, n);  // the sparse solve relies on its structural zeros
  factor_work.setZero(n);
  factor_inv_diag.setZero(n);
  // Doubles: by the evaluation plan, below (which writes them again for another model).
  if constexpr (!std::is_same_v<T, double>) WriteConstantFactorColumns(model, *this);
  joint_w.setZero(3, n);
  joint_v.setZero(3, n);
  momentum_lin.setZero(3, n);
  momentum_ang.setZero(3, n);
  composite_mass.setZero(n);
  composite_moment.setZero(3, n);
  composite_inertia.assign(n, Matrix3<T>::Zero());
  if (model.has_constraints()) {
    const int m = model.num_constraint_rows();
    constraint_B.setZero(m, n);
    constraint_velocity.setZero(m);
    constraint_bias.setZero(m);
    constraint_position.setZero(m);
    dependent.assign(static_cast<std::size_t>(m), 0);
    independent.assign(static_cast<std::size_t>(n - m), 0);
    constraint_A.setZero(m, n - m);
    reduced_M.setZero(n, n);
    reduced_f.setZero(n);
    lu.setZero(n, n);
    lu_pivots.assign(static_cast<std::size_t>(n), 0);
    pivot_scratch.setZero(m, n);
  }
  if constexpr (std::is_same_v<T, double>) internal::MakeEvaluationPlan(model, *this);
}

template struct Data<double>;
template struct Data<AutoDiff>;
template struct Data<Symbolic>;

}  // namespace hybridtest::multibody
