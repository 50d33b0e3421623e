// The Data<T> constructor: every workspace sized once. See data.h.
#include "hybridtest/multibody/data.h"

#include <algorithm>

namespace hybridtest::multibody {

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
  const ConstantMassPlan& constant = model.constant_mass();
  for (int j = 0; j < static_cast<int>(constant.factor_column.size()); ++j) {
    if (!constant.factor_column[static_cast<std::size_t>(j)]) continue;
    // Columns the factorisation skips (mass_solve.cc): L(i, j) at [i n + j], and 1/L_jj.
    factor_inv_diag(j) = T(constant.factor_inv_diag[static_cast<std::size_t>(j)]);
    for (int i = j + 1; i < n; ++i) {
      const std::size_t at = static_cast<std::size_t>(i) * n + j;
      cholesky_factor.data()[at] = T(constant.factor[at]);
    }
  }
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
}

template struct Data<double>;
template struct Data<AutoDiff>;
template struct Data<Symbolic>;

}  // namespace hybridtest::multibody
