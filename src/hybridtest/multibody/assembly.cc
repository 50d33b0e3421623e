// Consistent states and linearisation of constrained models. See assembly.h.
#include "hybridtest/multibody/assembly.h"

#include <fmt/core.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "hybridtest/common/error.h"
#include "hybridtest/multibody/constraints.h"
#include "hybridtest/multibody/kane.h"

namespace hybridtest::multibody {

namespace {

// m columns of a (m × n) by complete pivoting (ascending), or empty if a is rank-deficient.
std::vector<int> PivotColumns(Eigen::MatrixXd a) {
  const int m = static_cast<int>(a.rows());
  std::vector<int> cols;
  const double scale = a.lpNorm<Eigen::Infinity>();  // 0 for an empty a
  for (int k = 0; k < m; ++k) {
    int bi = -1, bj = -1;
    double best = -1.0;
    for (int i = k; i < m; ++i)
      for (int j = 0; j < a.cols(); ++j) {
        if (std::find(cols.begin(), cols.end(), j) != cols.end()) continue;
        if (std::abs(a(i, j)) > best) {
          best = std::abs(a(i, j));
          bi = i;
          bj = j;
        }
      }
    if (!(best > 1e-12 * scale)) return {};
    a.row(k).swap(a.row(bi));
    cols.push_back(bj);
    for (int i = k + 1; i < m; ++i) a.row(i) -= a(i, bj) / a(k, bj) * a.row(k);
  }
  std::sort(cols.begin(), cols.end());
  return cols;
}

std::vector<int> Complement(const std::vector<int>& set, int n) {
  std::vector<int> out;
  for (int j = 0; j < n; ++j)
    if (std::find(set.begin(), set.end(), j) == set.end()) out.push_back(j);
  return out;
}

// The holonomic rows' f and ∂f/∂q = B_h W⁻¹ at data's last kinematics and constraints.
void HolonomicRows(const Model& model, const Data<double>& data, Eigen::VectorXd& f,
                   Eigen::MatrixXd& f_q) {
  const int mh = model.num_holonomic_rows();
  const int n = data.n;
  f.resize(mh);
  Eigen::MatrixXd Bh(mh, n);
  int h = 0;
  for (int s = 0; s < model.num_constraint_rows(); ++s) {
    if (!model.constraint_rows()[static_cast<std::size_t>(s)].holonomic) continue;
    f(h) = data.constraint_position(s);
    Bh.row(h) = data.constraint_B.row(s);
    ++h;
  }
  f_q = model.has_identity_kinematics() ? Bh : Eigen::MatrixXd(Bh * data.W.inverse());
}

std::vector<int> DependentCoordinates(const Model& model, const Eigen::MatrixXd& f_q) {
  const std::vector<int>& chosen = model.constraint_options().dependent_coordinates;
  if (!chosen.empty()) return chosen;
  std::vector<int> cols = PivotColumns(f_q);
  if (cols.empty() && f_q.rows() > 0) {
    throw ModelError("the holonomic constraints are redundant at this configuration (∂f/∂q is "
                     "rank-deficient): remove the redundant ones");
  }
  return cols;
}

}  // namespace

ConstraintResiduals CalcConstraintResiduals(const Model& model, double t,
                                            const Eigen::VectorXd& x) {
  ConstraintResiduals out;
  if (!model.has_constraints()) return out;
  Data<double> data(model);
  CalcKinematics<double>(model, data, t, x);
  CalcConstraints(model, data);
  for (int s = 0; s < model.num_constraint_rows(); ++s) {
    const double f = std::abs(data.constraint_position(s));
    if (f > out.position || out.worst_row < 0) {
      if (model.constraint_rows()[static_cast<std::size_t>(s)].holonomic || out.worst_row < 0) {
        out.worst_row = s;
      }
    }
    out.position = std::max(out.position, f);
    out.velocity = std::max(out.velocity, std::abs(data.constraint_velocity(s)));
  }
  return out;
}

AssembledState AssembleState(const Model& model, double t, const Eigen::VectorXd& x) {
  AssembledState out{x, {}, 0.0, 0.0};
  if (!model.has_constraints()) return out;
  const int n = model.num_coordinates();
  Data<double> data(model);
  Eigen::VectorXd f;
  Eigen::MatrixXd f_q;
  // Newton's method on the dependent coordinates.
  if (model.num_holonomic_rows() > 0) {
    for (int iter = 0; iter < 60; ++iter) {
      CalcKinematics<double>(model, data, t, out.x);
      CalcConstraints(model, data);
      HolonomicRows(model, data, f, f_q);
      if (iter == 0) out.dependent_coordinates = DependentCoordinates(model, f_q);
      if (f.cwiseAbs().maxCoeff() == 0.0) break;
      const std::vector<int>& dep = out.dependent_coordinates;
      Eigen::MatrixXd f_qd(f.size(), static_cast<Eigen::Index>(dep.size()));
      for (std::size_t k = 0; k < dep.size(); ++k) f_qd.col(static_cast<Eigen::Index>(k)) = f_q.col(dep[k]);
      const Eigen::FullPivLU<Eigen::MatrixXd> lu(f_qd);
      if (!lu.isInvertible()) break;
      const Eigen::VectorXd step = lu.solve(-f);
      if (!step.allFinite()) break;
      for (std::size_t k = 0; k < dep.size(); ++k) out.x(dep[k]) += step(static_cast<Eigen::Index>(k));
      if (step.cwiseAbs().maxCoeff() <= 1e-15 * (1.0 + out.x.head(n).cwiseAbs().maxCoeff())) break;
    }
  }
  CalcKinematics<double>(model, data, t, out.x);
  CalcConstraints(model, data);
  const ConstraintResiduals before = CalcConstraintResiduals(model, t, out.x);
  if (!(before.position <= model.constraint_options().tolerance)) {
    throw ModelError(fmt::format(
        "the constraints cannot be met at this configuration: constraint '{}' keeps a residual "
        "|f| = {:.3g} (tolerance {:.3g}) after Newton's method on the dependent coordinates; "
        "give independent coordinates the mechanism can reach (e.g. a loop that can close), or "
        "check the constraint's geometry",
        ConstraintRowName(model, before.worst_row), before.position,
        model.constraint_options().tolerance));
  }
  // The dependent speeds from the independent ones.
  if (!ChooseDependentSpeeds(model, data)) {
    throw ModelError("the velocity constraints are redundant at this configuration (B is "
                     "rank-deficient): remove the redundant ones");
  }
  const int m = model.num_constraint_rows();
  Eigen::MatrixXd Bd(m, m);
  Eigen::VectorXd rhs = -(data.constraint_velocity - data.constraint_B * data.u);
  for (int k = 0; k < m; ++k) Bd.col(k) = data.constraint_B.col(data.dependent[k]);
  for (int j : data.independent) rhs -= data.constraint_B.col(j) * data.u(j);
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(Bd);
  if (!lu.isInvertible()) {
    std::string names;
    for (int j : data.dependent) names += (names.empty() ? "" : ", ") + model.speeds()[j].name;
    throw ModelError(fmt::format("the dependent speeds {} cannot be solved from the velocity "
                                 "constraints here (their columns of B are singular); choose "
                                 "other dependent speeds", names));
  }
  const Eigen::VectorXd ud = lu.solve(rhs);
  for (int k = 0; k < m; ++k) out.x(n + data.dependent[k]) = ud(k);
  const ConstraintResiduals after = CalcConstraintResiduals(model, t, out.x);
  out.position_residual = after.position;
  out.velocity_residual = after.velocity;
  return out;
}

Linearization LinearizeConstrained(const Model& model, double t, const Eigen::VectorXd& x,
                                   const std::vector<double>& slot_stiffness) {
  const int n = model.num_coordinates();
  const int nz = model.num_extra_states();
  const int nx = model.num_states();
  Linearization out;
  // J = dẋ/dx with r = k d(q), exact (AutoDiff), in chunks of kMaxDerivatives states.
  Eigen::MatrixXd J(nx, nx);
  {
    Data<AutoDiff> data(model);
    VectorX<AutoDiff> xa(nx), xdot(nx), r(model.num_slots()), d(model.num_slots());
    for (int first = 0; first < nx; first += kMaxDerivatives) {
      const int k = std::min(kMaxDerivatives, nx - first);
      for (int i = 0; i < nx; ++i) {
        xa(i) = AutoDiff(x(i), Derivatives::Zero(k));
        if (i >= first && i < first + k) xa(i).derivatives()(i - first) = 1.0;
      }
      const AutoDiff ta(t, Derivatives::Zero(k));
      CalcSlotDisplacements<AutoDiff>(model, data, ta, xa.head(n), d);
      for (int s = 0; s < model.num_slots(); ++s) {
        const double ks = slot_stiffness.empty() ? 0.0 : slot_stiffness[static_cast<std::size_t>(s)];
        r(s) = AutoDiff(ks * d(s).value(), ks * d(s).derivatives());
        if (r(s).derivatives().size() != k) r(s).derivatives() = Derivatives::Zero(k);
      }
      CalcStateDerivative<AutoDiff>(model, data, ta, xa, r, xdot);
      for (int i = 0; i < nx; ++i) {
        const Derivatives& dd = xdot(i).derivatives();
        for (int c = 0; c < k; ++c) J(i, first + c) = c < dd.size() ? dd(c) : 0.0;
      }
    }
  }
  auto name_of = [&](int i) {
    if (i < n) return model.coordinates()[i].name;
    if (i < 2 * n) return model.speeds()[i - n].name;
    return model.extra_states()[i - 2 * n].info.name;
  };
  if (!model.has_constraints()) {
    out.A = J;
    out.J = J;
    out.T = Eigen::MatrixXd::Identity(nx, nx);
    for (int i = 0; i < nx; ++i) {
      out.states.push_back(i);
      out.state_names.push_back(name_of(i));
    }
    return out;
  }
  const int m = model.num_constraint_rows();
  Data<double> data(model);
  CalcKinematics<double>(model, data, t, x);
  CalcConstraints(model, data);
  if (!ChooseDependentSpeeds(model, data)) {
    throw ModelError("the velocity constraints are redundant at the operating point");
  }
  Eigen::VectorXd f;
  Eigen::MatrixXd f_q;
  HolonomicRows(model, data, f, f_q);
  const std::vector<int> dep_q = DependentCoordinates(model, f_q);
  const std::vector<int> ind_q = Complement(dep_q, n);
  // G_q = ∂(B u + c)/∂q, exact, in chunks of kMaxDerivatives coordinates.
  Eigen::MatrixXd G_q = Eigen::MatrixXd::Zero(m, n);
  Data<AutoDiff> ad(model);
  VectorX<AutoDiff> xa(nx);
  for (int first = 0; first < n; first += kMaxDerivatives) {
    const int k = std::min(kMaxDerivatives, n - first);
    for (int i = 0; i < nx; ++i) {
      xa(i) = AutoDiff(x(i), Derivatives::Zero(k));
      if (i >= first && i < first + k) xa(i).derivatives()(i - first) = 1.0;
    }
    CalcKinematics<AutoDiff>(model, ad, AutoDiff(t, Derivatives::Zero(k)), xa);
    CalcConstraints(model, ad);
    for (int s = 0; s < m; ++s) {
      const Derivatives& d = ad.constraint_velocity(s).derivatives();
      for (int c = 0; c < k && c < d.size(); ++c) G_q(s, first + c) = d(c);
    }
  }
  // The tangent T = ∂x/∂x_i.
  Eigen::MatrixXd Bd(m, m);
  for (int k = 0; k < m; ++k) Bd.col(k) = data.constraint_B.col(data.dependent[k]);
  const Eigen::FullPivLU<Eigen::MatrixXd> bd(Bd);
  Eigen::MatrixXd f_qd(f_q.rows(), static_cast<Eigen::Index>(dep_q.size()));
  for (std::size_t k = 0; k < dep_q.size(); ++k) f_qd.col(static_cast<Eigen::Index>(k)) = f_q.col(dep_q[k]);
  const Eigen::FullPivLU<Eigen::MatrixXd> fd(f_qd);
  const int ni = static_cast<int>(ind_q.size()) + static_cast<int>(data.independent.size()) + nz;
  Eigen::MatrixXd T = Eigen::MatrixXd::Zero(nx, ni);
  int col = 0;
  for (int k : ind_q) {
    Eigen::VectorXd dq = Eigen::VectorXd::Unit(n, k);
    if (!dep_q.empty()) {
      const Eigen::VectorXd d = fd.solve(-f_q.col(k));
      for (std::size_t s = 0; s < dep_q.size(); ++s) dq(dep_q[s]) = d(static_cast<Eigen::Index>(s));
    }
    T.col(col).head(n) = dq;
    const Eigen::VectorXd du = bd.solve(-(G_q * dq));
    for (int s = 0; s < m; ++s) T(n + data.dependent[s], col) = du(s);
    out.states.push_back(k);
    ++col;
  }
  for (int j : data.independent) {
    T(n + j, col) = 1.0;
    const Eigen::VectorXd du = bd.solve(-data.constraint_B.col(j));
    for (int s = 0; s < m; ++s) T(n + data.dependent[s], col) = du(s);
    out.states.push_back(n + j);
    ++col;
  }
  for (int k = 0; k < nz; ++k) {
    T(2 * n + k, col++) = 1.0;
    out.states.push_back(2 * n + k);
  }
  Eigen::MatrixXd PJ(ni, nx);
  for (int i = 0; i < ni; ++i) PJ.row(i) = J.row(out.states[static_cast<std::size_t>(i)]);
  out.A = PJ * T;
  out.J = std::move(J);
  out.T = std::move(T);
  for (int i : out.states) out.state_names.push_back(name_of(i));
  return out;
}

}  // namespace hybridtest::multibody
