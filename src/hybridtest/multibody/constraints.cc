// Constrained Kane's equations: the constraint rows, the choice of dependent speeds, the
// reduced equations and the constrained state derivative. See constraints.h.
#include "hybridtest/multibody/constraints.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "hybridtest/common/error.h"
#include "hybridtest/multibody/field_eval.h"
#include "hybridtest/multibody/kane.h"
#include "hybridtest/multibody/lu.h"

namespace hybridtest::multibody {

namespace {
template <typename T>
T Dot3(const Vector3<T>& a, const Vector3<T>& b) {
  return internal::Dot(a.data(), b.data());
}
template <typename T>
Vector3<T> Cross3(const Vector3<T>& a, const Vector3<T>& b) {
  Vector3<T> out;
  internal::Cross(a.data(), b.data(), out.data());
  return out;
}
}  // namespace

std::string ConstraintRowName(const Model& model, int row) {
  const ConstraintRow& r = model.constraint_rows()[static_cast<std::size_t>(row)];
  const ConstraintSpec& c = model.constraints()[static_cast<std::size_t>(r.constraint)];
  if (c.components.empty()) return c.name;
  return fmt::format("{} ({})", c.name, "xyz"[r.component]);
}

template <typename T>
void CalcConstraints(const Model& model, Data<T>& data) {
  const int n = data.n;
  // The planar fast path does not seed the jets a general constraint expression reads.
  if (model.has_general_fields()) internal::SeedCoordinateJets(data, true);
  MatrixX<T>& B = data.constraint_B;
  int row = 0;
  for (const ConstraintSpec& c : model.constraints()) {
    switch (c.kind) {
      case ConstraintSpec::Kind::kHolonomic: {
        // f(q, t): B = ∂f/∂q W, B u + c = ḟ, bias = f̈ with u̇ = 0.
        const internal::FieldEval<T> e =
            internal::EvalField(model, data, c.field, data.partial_rate.data());
        for (int j = 0; j < n; ++j) B(row, j) = data.partial_rate(j);
        data.constraint_position(row) = e.v;
        data.constraint_velocity(row) = e.d1;
        data.constraint_bias(row) = e.d2;
        ++row;
        break;
      }
      case ConstraintSpec::Kind::kNonholonomic: {
        // Σ B_j(q, t) u_j + c(q, t): bias = Σ Ḃ_j u_j + ċ.
        const internal::FieldEval<T> e0 =
            internal::EvalField(model, data, c.constant, static_cast<T*>(nullptr));
        for (int j = 0; j < n; ++j) B(row, j) = T(0.0);
        T velocity = e0.v;
        T bias = e0.d1;
        for (const auto& [j, field] : c.coefficients) {
          const internal::FieldEval<T> e =
              internal::EvalField(model, data, field, static_cast<T*>(nullptr));
          B(row, j) = internal::Add(B(row, j), e.v);
          velocity = internal::Add(velocity, internal::Mul(e.v, data.u(j)));
          bias = internal::Add(bias, internal::Mul(e.d1, data.u(j)));
        }
        data.constraint_position(row) = T(0.0);
        data.constraint_velocity(row) = velocity;
        data.constraint_bias(row) = bias;
        ++row;
        break;
      }
      case ConstraintSpec::Kind::kCoincident: {
        // e·d with d = p_P − p_Q and e a unit vector of E: d/dt = e·ḋ + (ω_E × e)·d.
        const int E = c.expressed_in;
        const Vector3<T> d = data.p_OP[c.point] - data.p_OP[c.other];
        const Vector3<T> dd = data.v_NP[c.point] - data.v_NP[c.other];
        const Vector3<T> a = data.a_rem[c.point] - data.a_rem[c.other];
        for (int comp : c.components) {
          const Vector3<T> e = data.R_NF[E].col(comp);
          const Vector3<T> we = Cross3(data.w_NF[E], e);
          data.constraint_position(row) = Dot3(e, d);
          data.constraint_velocity(row) = internal::Add(Dot3(e, dd), Dot3(we, d));
          const Vector3<T> ee = Cross3(data.alpha_rem[E], e) + Cross3(data.w_NF[E], we);
          data.constraint_bias(row) =
              internal::Add(internal::Add(Dot3(e, a), T(2.0 * Dot3(we, dd))), Dot3(ee, d));
          for (int j = 0; j < n; ++j) {
            const Vector3<T> vj = data.v_partial[c.point].col(j) - data.v_partial[c.other].col(j);
            const Vector3<T> wj = data.w_partial[E].col(j);
            B(row, j) = internal::Add(Dot3(e, vj), Dot3(Cross3(wj, e), d));
          }
          ++row;
        }
        break;
      }
      case ConstraintSpec::Kind::kVelocity: {
        // v = v_C + ω_F × ρ (ρ = p_P − p_C) for the point of body F at P, else P's own.
        Vector3<T> v = data.v_NP[c.point];
        Vector3<T> a = data.a_rem[c.point];
        Vector3<T> rho = Vector3<T>::Zero();
        if (c.body >= 0) {
          const int C = c.body_point;
          const int F = c.body;
          rho = data.p_OP[c.point] - data.p_OP[C];
          const Vector3<T> rho_dot = data.v_NP[c.point] - data.v_NP[C];
          v = data.v_NP[C] + Cross3(data.w_NF[F], rho);
          a = data.a_rem[C] + Cross3(data.alpha_rem[F], rho) + Cross3(data.w_NF[F], rho_dot);
        }
        const int E = c.expressed_in;
        for (int comp : c.components) {
          const Vector3<T> e = data.R_NF[E].col(comp);
          const Vector3<T> we = Cross3(data.w_NF[E], e);
          data.constraint_position(row) = T(0.0);
          data.constraint_velocity(row) = Dot3(e, v);
          data.constraint_bias(row) = internal::Add(Dot3(we, v), Dot3(e, a));
          for (int j = 0; j < n; ++j) {
            Vector3<T> vj;
            if (c.body >= 0) {
              vj = data.v_partial[c.body_point].col(j) +
                   Cross3(Vector3<T>(data.w_partial[c.body].col(j)), rho);
            } else {
              vj = data.v_partial[c.point].col(j);
            }
            B(row, j) = Dot3(e, vj);
          }
          ++row;
        }
        break;
      }
    }
  }
}

template <typename T>
bool ChooseDependentSpeeds(const Model& model, Data<T>& data) {
  const int n = data.n;
  const int m = model.num_constraint_rows();
  const std::vector<int>& chosen = model.constraint_options().dependent_speeds;
  std::vector<int>& dep = data.dependent;
  if (!chosen.empty()) {
    std::copy(chosen.begin(), chosen.end(), dep.begin());
  } else {
    // Complete pivoting on B's values: the largest remaining entry picks a speed each step.
    Eigen::MatrixXd& a = data.pivot_scratch;
    double scale = 0.0;
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < n; ++j) {
        a(i, j) = ValueOf(data.constraint_B(i, j));
        scale = std::max(scale, std::abs(a(i, j)));
      }
    for (int k = 0; k < m; ++k) {
      int bi = k, bj = -1;
      double best = -1.0;
      for (int i = k; i < m; ++i) {
        for (int j = 0; j < n; ++j) {
          if (std::find(dep.begin(), dep.begin() + k, j) != dep.begin() + k) continue;
          if (std::abs(a(i, j)) > best) {
            best = std::abs(a(i, j));
            bi = i;
            bj = j;
          }
        }
      }
      if (!(best > 1e-12 * scale) || bj < 0) return false;
      a.row(k).swap(a.row(bi));
      dep[static_cast<std::size_t>(k)] = bj;
      for (int i = k + 1; i < m; ++i) {
        const double f = a(i, bj) / a(k, bj);
        a.row(i) -= f * a.row(k);
      }
    }
    std::sort(dep.begin(), dep.end());
  }
  int p = 0;
  for (int j = 0; j < n; ++j) {
    if (std::find(dep.begin(), dep.end(), j) == dep.end()) data.independent[p++] = j;
  }
  return true;
}

template <typename T>
void CalcReducedEquations(const Model& model, Data<T>& data, bool stabilise) {
  const int n = data.n;
  const int m = model.num_constraint_rows();
  const int p = n - m;
  const MatrixX<T>& B = data.constraint_B;
  // B_d, factored in the corner of the LU scratch.
  for (int s = 0; s < m; ++s)
    for (int k = 0; k < m; ++k) data.lu(s, k) = B(s, data.dependent[k]);
  if (!internal::LuFactor(data.lu, m, data.lu_pivots.data())) {
    std::string names;
    for (int j : data.dependent) names += (names.empty() ? "" : ", ") + model.speeds()[j].name;
    throw ModelError(fmt::format("the constraints cannot be solved for the dependent speeds {} "
                                 "at t = {} s: their columns of B are singular here; choose other "
                                 "dependent speeds (or leave the choice to the engine)",
                                 names, ValueOf(data.t)));
  }
  // A = −B_d⁻¹ B_i, column by column.
  VectorX<T>& column = data.partial_rate;
  for (int c = 0; c < p; ++c) {
    for (int s = 0; s < m; ++s) column(s) = -B(s, data.independent[c]);
    internal::LuSolve(data.lu, m, data.lu_pivots.data(), column.data());
    for (int s = 0; s < m; ++s) data.constraint_A(s, c) = column(s);
  }
  // Rows of the independent speeds: Cᵀ M and Cᵀ g.
  for (int c = 0; c < p; ++c) {
    const int i = data.independent[c];
    for (int k = 0; k < n; ++k) {
      T sum = data.M(i, k);
      for (int s = 0; s < m; ++s) {
        sum = internal::Add(sum, internal::Mul(data.constraint_A(s, c), data.M(data.dependent[s], k)));
      }
      data.reduced_M(c, k) = sum;
    }
    T f = data.g(i);
    for (int s = 0; s < m; ++s) {
      f = internal::Add(f, internal::Mul(data.constraint_A(s, c), data.g(data.dependent[s])));
    }
    data.reduced_f(c) = f;
  }
  // The acceleration constraints, stabilised if asked.
  const double tau = model.constraint_options().stabilisation_time_constant;
  const double alpha = stabilise && tau > 0.0 ? 1.0 / tau : 0.0;
  for (int s = 0; s < m; ++s) {
    for (int k = 0; k < n; ++k) data.reduced_M(p + s, k) = B(s, k);
    T rhs = -data.constraint_bias(s);
    if (alpha > 0.0) {
      rhs = internal::Sub(rhs, internal::Scale(2.0 * alpha, data.constraint_velocity(s)));
      if (model.constraint_rows()[static_cast<std::size_t>(s)].holonomic) {
        rhs = internal::Sub(rhs, internal::Scale(alpha * alpha, data.constraint_position(s)));
      }
    }
    data.reduced_f(p + s) = rhs;
  }
}

template <typename T>
void CalcConstrainedStateDerivative(const Model& model, Data<T>& data, const T& t,
                                    const Eigen::Ref<const VectorX<T>>& x,
                                    const Eigen::Ref<const VectorX<T>>& r,
                                    Eigen::Ref<VectorX<T>> xdot) {
  const int n = data.n;
  // A compiled model (symbolic_compiled.h) gives M, g, q̇, ż and the constraint rows; the
  // choice of dependent speeds, the reduction and the solve below are the same either way.
  bool compiled = false;
  if constexpr (std::is_same_v<T, double>) {
    if (model.compiled_rhs() != nullptr) {
      internal::CalcCompiledRhs(model, data, t, x, r);
      compiled = true;
    }
  }
  if (!compiled) {
    CalcKinematics(model, data, t, x);
    CalcMassMatrix(model, data);
    CalcForcing(model, data, r);
    CalcConstraints(model, data);
  }
  if (!ChooseDependentSpeeds(model, data)) {
    throw ModelError(fmt::format("the constraints are redundant or contradictory at t = {} s "
                                 "(B has rank < {}, its number of rows): remove the redundant "
                                 "ones", ValueOf(t), model.num_constraint_rows()));
  }
  CalcReducedEquations(model, data, true);
  data.lu = data.reduced_M;
  if (!internal::LuFactor(data.lu, n, data.lu_pivots.data())) {
    throw ModelError(fmt::format("the reduced equations [Cᵀ M; B] are singular at t = {} s: a "
                                 "mass or inertia is missing, or the constraints lock the "
                                 "mechanism", ValueOf(t)));
  }
  data.udot = data.reduced_f;
  internal::LuSolve(data.lu, n, data.lu_pivots.data(), data.udot.data());
  for (int k = 0; k < n; ++k) {
    xdot(k) = data.qdot(k);
    xdot(n + k) = data.udot(k);
  }
  if (compiled) {
    xdot.tail(model.num_extra_states()) = data.zdot;
  } else {
    internal::CalcExtraStateRates(model, data, xdot);
  }
}

void CalcConstrainedRateCoupling(const Model& model, Data<double>& data,
                                 const Eigen::Ref<const Eigen::MatrixXd>& B_r,
                                 Eigen::Ref<Eigen::MatrixXd> out) {
  const int n = data.n;
  const int m = model.num_constraint_rows();
  const int p = n - m;
  data.lu = data.reduced_M;
  if (!internal::LuFactor(data.lu, n, data.lu_pivots.data())) {
    throw ModelError("the reduced equations [Cᵀ M; B] are singular here");
  }
  for (Eigen::Index s = 0; s < B_r.cols(); ++s) {
    double* column = out.col(s).data();
    for (int c = 0; c < p; ++c) {
      double sum = B_r(data.independent[c], s);
      for (int k = 0; k < m; ++k) sum += data.constraint_A(k, c) * B_r(data.dependent[k], s);
      column[c] = sum;
    }
    for (int k = 0; k < m; ++k) column[p + k] = 0.0;
    internal::LuSolve(data.lu, n, data.lu_pivots.data(), column);
  }
}

void CalcConstraintForces(const Model& model, Data<double>& data,
                          Eigen::Ref<Eigen::VectorXd> lambda) {
  const int n = data.n;
  const int m = model.num_constraint_rows();
  for (int s = 0; s < m; ++s)
    for (int k = 0; k < m; ++k) data.lu(k, s) = data.constraint_B(s, data.dependent[k]);
  if (!internal::LuFactor(data.lu, m, data.lu_pivots.data())) {
    throw ModelError("the constraint forces cannot be solved here: the columns of B of the "
                     "dependent speeds are singular");
  }
  for (int k = 0; k < m; ++k) {
    const int j = data.dependent[k];
    double v = -data.g(j);
    for (int i = 0; i < n; ++i) v += data.M(j, i) * data.udot(i);
    lambda(k) = v;
  }
  internal::LuSolve(data.lu, m, data.lu_pivots.data(), lambda.data());
}

#define HYBRIDTEST_INSTANTIATE(T)                                                        \
  template bool ChooseDependentSpeeds<T>(const Model&, Data<T>&);                        \
  template void CalcReducedEquations<T>(const Model&, Data<T>&, bool);                   \
  template void CalcConstrainedStateDerivative<T>(                                       \
      const Model&, Data<T>&, const T&, const Eigen::Ref<const VectorX<T>>&,             \
      const Eigen::Ref<const VectorX<T>>&, Eigen::Ref<VectorX<T>>);
HYBRIDTEST_INSTANTIATE(double)
HYBRIDTEST_INSTANTIATE(AutoDiff)
#undef HYBRIDTEST_INSTANTIATE
template void CalcConstraints<double>(const Model&, Data<double>&);
template void CalcConstraints<AutoDiff>(const Model&, Data<AutoDiff>&);
template void CalcConstraints<Symbolic>(const Model&, Data<Symbolic>&);

}  // namespace hybridtest::multibody
