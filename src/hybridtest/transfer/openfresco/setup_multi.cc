// See setup.h: an OpenFresco setup of several actuators, T (n_act × n).
#include <Eigen/Dense>
#include <fmt/core.h>

#include <cmath>
#include <limits>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/openfresco/setup.h"

namespace hybridtest::transfer::openfresco {
namespace {

using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

Eigen::MatrixXd T(const ExpSetup& s) {
  return Eigen::Map<const RowMajor>(s.transform.data(), s.actuators, s.dofs());
}

std::vector<double> ToVector(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

}  // namespace

void ValidateMultiSetup(const ExpSetup& s) {
  const auto na = static_cast<std::size_t>(s.actuators);
  if (s.actuators < 1 || s.transform.empty() || s.transform.size() % na != 0 ||
      s.p0s.size() != na || s.stiffness_matrix.size() != na * na) {
    throw ConfigError(fmt::format("openfresco: {} actuators, a transform of {} values, {} p0 and "
                                  "a stiffness of {} values: expected T of n_act rows, one p0 per "
                                  "actuator and an n_act × n_act stiffness", s.actuators,
                                  s.transform.size(), s.p0s.size(), s.stiffness_matrix.size()));
  }
  const Eigen::MatrixXd t = T(s);
  if (!t.allFinite() || Eigen::FullPivLU<Eigen::MatrixXd>(t).rank() < s.actuators) {
    throw ConfigError(fmt::format("openfresco.transform ({} × {}): expected finite rows that are "
                                  "linearly independent (each actuator its own direction)",
                                  s.actuators, s.dofs()));
  }
}

std::vector<double> ActuatorCommands(const ExpSetup& s, std::span<const double> d) {
  std::vector<double> a(static_cast<std::size_t>(s.actuators),
                        std::numeric_limits<double>::quiet_NaN());
  for (const double v : d) {
    if (!std::isfinite(v)) return a;
  }
  const Eigen::VectorXd x =
      T(s) * Eigen::Map<const Eigen::VectorXd>(d.data(), static_cast<Eigen::Index>(d.size()));
  for (std::size_t k = 0; k < a.size(); ++k) {
    a[k] = s.p0s[k] + x(static_cast<Eigen::Index>(k)) * s.wire_units.metres_per_length_unit;
  }
  return a;
}

std::vector<double> ElementForcesOf(const ExpSetup& s, std::span<const double> forces) {
  const Eigen::VectorXd f =
      Eigen::Map<const Eigen::VectorXd>(forces.data(), static_cast<Eigen::Index>(forces.size())) /
      s.wire_units.newtons_per_force_unit;
  return ToVector(T(s).transpose() * f);
}

std::vector<double> ElementStiffnessOf(const ExpSetup& s) {
  const Eigen::MatrixXd k = Eigen::Map<const RowMajor>(s.stiffness_matrix.data(), s.actuators,
                                                       s.actuators) *
                            (s.wire_units.metres_per_length_unit /
                             s.wire_units.newtons_per_force_unit);
  const Eigen::MatrixXd kd = T(s).transpose() * k * T(s);  // column-major storage
  return {kd.data(), kd.data() + kd.size()};
}

std::vector<double> ElementDisplacementOf(const ExpSetup& s, std::span<const double> offsets) {
  const Eigen::MatrixXd t = T(s);
  const Eigen::VectorXd x =
      Eigen::Map<const Eigen::VectorXd>(offsets.data(), static_cast<Eigen::Index>(offsets.size())) /
      s.wire_units.metres_per_length_unit;
  return ToVector(t.transpose() * (t * t.transpose()).ldlt().solve(x));
}

std::vector<double> ProjectOnActuators(const ExpSetup& s, std::span<const double> v) {
  const Eigen::MatrixXd t = T(s);
  const Eigen::VectorXd tv =
      t * Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
  return ToVector(t.transpose() * (t * t.transpose()).ldlt().solve(tv));
}

}  // namespace hybridtest::transfer::openfresco
