// See setup.h.
#include "hybridtest/transfer/openfresco/setup.h"

#include <Eigen/Dense>
#include <fmt/core.h>

#include <cmath>
#include <limits>

#include "hybridtest/common/error.h"

namespace hybridtest::transfer::openfresco {
namespace {

// T_ki: row k (actuator), column i (element dof).
double T(const ExpSetup& s, std::size_t k, std::size_t i) {
  return s.transform[k * static_cast<std::size_t>(s.dofs()) + i];
}

// Row k of T.
std::span<const double> Row(const ExpSetup& s, std::size_t k) {
  const auto n = static_cast<std::size_t>(s.dofs());
  return std::span<const double>(s.transform).subspan(k * n, n);
}

double Dot(std::span<const double> a, std::span<const double> b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) s += a[i] * b[i];
  return s;
}

// y = (T Tᵀ)⁻¹ b (n_act); for one actuator the division by |t|².
std::vector<double> SolveGram(const ExpSetup& s, std::span<const double> b) {
  const auto na = static_cast<std::size_t>(s.actuators);
  if (na == 1) return {b[0] / Dot(s.transform, s.transform)};
  Eigen::MatrixXd gram(s.actuators, s.actuators);
  for (std::size_t k = 0; k < na; ++k) {
    for (std::size_t l = 0; l < na; ++l) {
      gram(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(l)) = Dot(Row(s, k), Row(s, l));
    }
  }
  const Eigen::VectorXd y =
      gram.ldlt().solve(Eigen::Map<const Eigen::VectorXd>(b.data(), s.actuators));
  return {y.data(), y.data() + y.size()};
}

// Tᵀ y (n), the first term first (so that one actuator gives t_i · y exactly).
std::vector<double> TransposeTimes(const ExpSetup& s, std::span<const double> y) {
  const auto n = static_cast<std::size_t>(s.dofs());
  std::vector<double> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    double sum = T(s, 0, i) * y[0];
    for (std::size_t k = 1; k < y.size(); ++k) sum += T(s, k, i) * y[k];
    out[i] = sum;
  }
  return out;
}

}  // namespace

void ValidateSetup(const ExpSetup& s) {
  if (s.transform.empty()) {
    throw ConfigError("openfresco.transform: empty; expected one row [[t1, ..., tn]] per actuator");
  }
  const auto na = static_cast<std::size_t>(std::max(s.actuators, 0));
  if (s.actuators < 1 || s.transform.size() % na != 0 || s.p0s.size() != na ||
      s.stiffness_matrix.size() != na * na) {
    throw ConfigError(fmt::format("openfresco: {} actuators, a transform of {} values, {} p0 and "
                                  "a stiffness of {} values: expected T of n_act rows, one p0 per "
                                  "actuator and an n_act × n_act stiffness", s.actuators,
                                  s.transform.size(), s.p0s.size(), s.stiffness_matrix.size()));
  }
  const auto n = static_cast<std::size_t>(s.dofs());
  for (std::size_t k = 0; k < na; ++k) {
    // Rows named [k] only where there are several.
    const std::string row = na == 1 ? "" : fmt::format("[{}]", k);
    bool any = false;
    for (std::size_t i = 0; i < n; ++i) {
      if (!std::isfinite(T(s, k, i))) {
        throw ConfigError(fmt::format("openfresco.transform[{}][{}] = {}: expected a finite "
                                      "number", k, i, T(s, k, i)));
      }
      any = any || T(s, k, i) != 0.0;
    }
    if (!any) {
      throw ConfigError(fmt::format("openfresco.transform{}: all zero; the actuator would never "
                                    "move", row));
    }
    // The element forces, stiffness and displacements divide by |t|²: a row of 1e-200 would
    // underflow to 0 and send inf/NaN on the wire. A transform row is a set of direction
    // cosines and scales of order 1.
    const double norm = std::sqrt(Dot(Row(s, k), Row(s, k)));
    if (!(norm >= 1e-6 && norm <= 1e6)) {
      throw ConfigError(fmt::format("openfresco.transform{}: |t| = {}: expected a row of "
                                    "direction cosines and scales with a length from 1e-6 to 1e6 "
                                    "(e.g. [[1.0]] or [[0.0, 1.0]])", row, norm));
    }
    if (!std::isfinite(s.p0s[k])) {
      throw ConfigError(fmt::format("openfresco: p0{} is not finite", row));
    }
    for (std::size_t l = 0; l < na; ++l) {
      const double kkl = s.stiffness_matrix[k * na + l];
      if (!std::isfinite(kkl) || (k == l && kkl < 0.0)) {
        throw ConfigError(fmt::format("openfresco.initial_stiffness{} = {} N/m: expected a "
                                      "finite value{}", na == 1 ? "" : fmt::format("[{}][{}]", k, l),
                                      kkl, k == l ? " >= 0" : ""));
      }
    }
  }
  if (na > 1) {
    Eigen::MatrixXd t(s.actuators, s.dofs());
    for (std::size_t k = 0; k < na; ++k) {
      for (std::size_t i = 0; i < n; ++i) {
        t(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(i)) = T(s, k, i);
      }
    }
    if (Eigen::FullPivLU<Eigen::MatrixXd>(t).rank() < s.actuators) {
      throw ConfigError(fmt::format("openfresco.transform ({} × {}): expected rows that are "
                                    "linearly independent (each actuator its own direction)",
                                    s.actuators, s.dofs()));
    }
  }
}

std::vector<double> ActuatorCommands(const ExpSetup& s, std::span<const double> d) {
  const auto na = static_cast<std::size_t>(s.actuators);
  std::vector<double> a(na, std::numeric_limits<double>::quiet_NaN());
  for (const double v : d) {
    if (!std::isfinite(v)) return a;
  }
  for (std::size_t k = 0; k < na; ++k) {
    a[k] = s.p0s[k] + Dot(Row(s, k), d) * s.wire_units.metres_per_length_unit;
  }
  return a;
}

std::vector<double> ElementForces(const ExpSetup& s, std::span<const double> forces) {
  std::vector<double> f(forces.size());
  for (std::size_t k = 0; k < f.size(); ++k) f[k] = forces[k] / s.wire_units.newtons_per_force_unit;
  return TransposeTimes(s, f);
}

std::vector<double> ElementStiffness(const ExpSetup& s) {
  const auto na = static_cast<std::size_t>(s.actuators);
  const auto n = static_cast<std::size_t>(s.dofs());
  std::vector<double> k(na * na);  // K_a in wire units
  for (std::size_t i = 0; i < k.size(); ++i) {
    k[i] = s.stiffness_matrix[i] * s.wire_units.metres_per_length_unit /
           s.wire_units.newtons_per_force_unit;
  }
  std::vector<double> out(n * n);
  for (std::size_t col = 0; col < n; ++col) {
    for (std::size_t row = 0; row < n; ++row) {
      double sum = 0.0;
      bool first = true;
      for (std::size_t a = 0; a < na; ++a) {
        for (std::size_t b = 0; b < na; ++b) {
          const double term = T(s, a, row) * k[a * na + b] * T(s, b, col);
          sum = first ? term : sum + term;
          first = false;
        }
      }
      out[col * n + row] = sum;
    }
  }
  return out;
}

std::vector<double> ElementDisplacement(const ExpSetup& s, std::span<const double> offsets) {
  const auto na = static_cast<std::size_t>(s.actuators);
  std::vector<double> x(na);
  for (std::size_t k = 0; k < na; ++k) x[k] = offsets[k] / s.wire_units.metres_per_length_unit;
  if (na == 1) {  // t x / |t|², in this order (the one-actuator setup's numbers)
    const double tt = Dot(s.transform, s.transform);
    std::vector<double> d(s.transform.size());
    for (std::size_t i = 0; i < d.size(); ++i) d[i] = s.transform[i] * x[0] / tt;
    return d;
  }
  return TransposeTimes(s, SolveGram(s, x));
}

std::vector<double> ProjectOnActuators(const ExpSetup& s, std::span<const double> v) {
  const auto na = static_cast<std::size_t>(s.actuators);
  std::vector<double> tv(na);
  for (std::size_t k = 0; k < na; ++k) tv[k] = Dot(Row(s, k), v);
  return TransposeTimes(s, SolveGram(s, tv));
}

}  // namespace hybridtest::transfer::openfresco
