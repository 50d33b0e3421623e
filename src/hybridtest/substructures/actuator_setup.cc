// See actuator_setup.h.
#include "hybridtest/substructures/actuator_setup.h"

#include <Eigen/Dense>
#include <fmt/core.h>

#include "hybridtest/common/error.h"

namespace hybridtest::substructures {

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

LinearActuatorSetup::LinearActuatorSetup(LinearSetup setup) : setup_(std::move(setup)) {
  setup_.Validate();
}

std::string LinearActuatorSetup::Describe() const {
  return fmt::format("linear setup a = p0 + T d, T {} × {}", num_actuators(), num_slots());
}

}  // namespace hybridtest::substructures
