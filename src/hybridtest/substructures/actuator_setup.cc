// See actuator_setup.h.
#include "hybridtest/substructures/actuator_setup.h"

#include <Eigen/Dense>
#include <fmt/core.h>

#include <cmath>

#include "hybridtest/common/error.h"

namespace hybridtest::substructures {

void SetupTransform::Validate() const {
  if (std::abs(sign) != 1.0 || std::abs(force_sign) != 1.0) {
    throw ConfigError(fmt::format("setup: sign = {}, force_sign = {}: expected +1 or -1", sign,
                                  force_sign));
  }
  if (!(scale > 0.0) || !(force_scale > 0.0) || !std::isfinite(scale) ||
      !std::isfinite(force_scale)) {
    throw ConfigError(fmt::format("setup: scale = {}, force_scale = {}: expected positive finite "
                                  "factors", scale, force_scale));
  }
  if (!std::isfinite(p0) || !std::isfinite(load_cell_zero)) {
    throw ConfigError("setup: p0 and load_cell_zero must be finite");
  }
}

void LinearSetup::Validate() const {
  const auto n = transform.rows(), m = transform.cols();
  if (n < 1 || m < 1 || p0.size() != n || load_cell_zero.size() != n) {
    throw ConfigError(fmt::format("setup: transform is {} × {}, p0 has {} values and "
                                  "load_cell_zero {}: expected T of n_actuators × n_slots, and "
                                  "one p0 and one load-cell zero per actuator (row of T)",
                                  n, m, p0.size(), load_cell_zero.size()));
  }
  if (!transform.allFinite() || !p0.allFinite() || !load_cell_zero.allFinite()) {
    throw ConfigError("setup: transform, p0 and load_cell_zero must be finite");
  }
  Eigen::FullPivLU<Eigen::MatrixXd> lu(transform);
  if (lu.rank() < m) {
    throw ConfigError(fmt::format("setup: transform ({} × {}) has rank {}: the actuators cannot "
                                  "tell the {} slots apart; give T full column rank", n, m,
                                  lu.rank(), m));
  }
}

void ActuatorSetup::CalcSlotForces(const Eigen::Ref<const Eigen::VectorXd>& d,
                                   const Eigen::Ref<const Eigen::VectorXd>& f,
                                   Eigen::Ref<Eigen::VectorXd> r) const {
  r.noalias() = CalcJacobian(d).transpose() * f;
}

Eigen::MatrixXd ActuatorSetup::SlotStiffness(const Eigen::MatrixXd& actuator_k) const {
  const Eigen::MatrixXd& t = linearisation();
  return t.transpose() * actuator_k * t;
}

Eigen::MatrixXd ActuatorSetup::ActuatorStiffness(const Eigen::MatrixXd& k0) const {
  const Eigen::MatrixXd& t = linearisation();
  const Eigen::MatrixXd pinv = (t.transpose() * t).ldlt().solve(t.transpose());  // m × n
  return pinv.transpose() * k0 * pinv;
}

ScalarSetup::ScalarSetup(const SetupTransform& transform)
    : s_(transform), p0_(Eigen::VectorXd::Constant(1, transform.p0)),
      zero_(Eigen::VectorXd::Constant(1, transform.load_cell_zero)),
      t_(Eigen::MatrixXd::Constant(1, 1, transform.sign * transform.scale)) {
  s_.Validate();
}

std::string ScalarSetup::Describe() const {
  return fmt::format("setup p0 = {} m, sign {}, scale {}, force sign {}, force scale {}, "
                     "load-cell zero {} N", s_.p0, s_.sign, s_.scale, s_.force_sign,
                     s_.force_scale, s_.load_cell_zero);
}

Eigen::MatrixXd ScalarSetup::SlotStiffness(const Eigen::MatrixXd& actuator_k) const {
  return Eigen::MatrixXd::Constant(
      1, 1, actuator_k(0, 0) * s_.sign * s_.scale * s_.force_sign * s_.force_scale);
}

Eigen::MatrixXd ScalarSetup::ActuatorStiffness(const Eigen::MatrixXd& k0) const {
  return Eigen::MatrixXd::Constant(
      1, 1, k0(0, 0) / (s_.sign * s_.scale * s_.force_sign * s_.force_scale));
}

LinearActuatorSetup::LinearActuatorSetup(LinearSetup setup) : setup_(std::move(setup)) {
  setup_.Validate();
}

std::string LinearActuatorSetup::Describe() const {
  return fmt::format("linear setup a = p0 + T d, T {} × {}", num_actuators(), num_slots());
}

}  // namespace hybridtest::substructures
