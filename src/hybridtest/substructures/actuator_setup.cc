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
  if (force_transform.size() == 0) return;
  if (force_transform.rows() != n || force_transform.cols() != m || !force_transform.allFinite() ||
      Eigen::FullPivLU<Eigen::MatrixXd>(force_transform).rank() < m) {
    throw ConfigError(fmt::format("setup: the force transform is {} × {}: expected finite values "
                                  "of full column rank, n_actuators × n_slots as T ({} × {})",
                                  force_transform.rows(), force_transform.cols(), n, m));
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

LinearActuatorSetup::LinearActuatorSetup(LinearSetup setup) : setup_(std::move(setup)) {
  setup_.Validate();
  scalar_ = num_actuators() == 1 && num_slots() == 1;
}

std::string LinearActuatorSetup::Describe() const {
  if (scalar_) {
    return fmt::format("setup p0 = {} m, T = {}, force factor {}, load-cell zero {} N",
                       setup_.p0(0), setup_.transform(0, 0), force_map()(0, 0),
                       setup_.load_cell_zero(0));
  }
  return fmt::format("linear setup a = p0 + T d, T {} × {}", num_actuators(), num_slots());
}

void LinearActuatorSetup::CalcSlotForces(const Eigen::Ref<const Eigen::VectorXd>& /*d*/,
                                         const Eigen::Ref<const Eigen::VectorXd>& f,
                                         Eigen::Ref<Eigen::VectorXd> r) const {
  if (scalar_) {
    r(0) = force_map()(0, 0) * f(0);
  } else {
    r.noalias() = force_map().transpose() * f;
  }
}

Eigen::MatrixXd LinearActuatorSetup::SlotStiffness(const Eigen::MatrixXd& actuator_k) const {
  const Eigen::MatrixXd& t = setup_.transform;
  if (scalar_) return Eigen::MatrixXd::Constant(1, 1, actuator_k(0, 0) * t(0, 0) * force_map()(0, 0));
  return force_map().transpose() * actuator_k * t;
}

Eigen::MatrixXd LinearActuatorSetup::ActuatorStiffness(const Eigen::MatrixXd& k0) const {
  const Eigen::MatrixXd& t = setup_.transform;
  if (scalar_) return Eigen::MatrixXd::Constant(1, 1, k0(0, 0) / (t(0, 0) * force_map()(0, 0)));
  auto pinv = [](const Eigen::MatrixXd& m) -> Eigen::MatrixXd {
    return (m.transpose() * m).ldlt().solve(m.transpose());  // m × n
  };
  if (setup_.force_transform.size() == 0) {
    const Eigen::MatrixXd p = pinv(t);
    return p.transpose() * k0 * p;
  }
  return pinv(force_map()).transpose() * k0 * pinv(t);
}

LinearSetup OneActuatorSetup(const SetupTransform& transform) {
  transform.Validate();
  LinearSetup setup;
  setup.p0 = Eigen::VectorXd::Constant(1, transform.p0);
  setup.transform = Eigen::MatrixXd::Constant(1, 1, transform.sign * transform.scale);
  setup.force_transform =
      Eigen::MatrixXd::Constant(1, 1, transform.force_sign * transform.force_scale);
  setup.load_cell_zero = Eigen::VectorXd::Constant(1, transform.load_cell_zero);
  return setup;
}

}  // namespace hybridtest::substructures
