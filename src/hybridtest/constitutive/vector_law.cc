// See vector_law.h.
#include "hybridtest/constitutive/vector_law.h"

#include <fmt/format.h>

#include "hybridtest/common/error.h"

namespace hybridtest::constitutive {

LinearCoupledLaw::LinearCoupledLaw(Eigen::MatrixXd stiffness) : k_(std::move(stiffness)) {
  if (k_.rows() < 1 || k_.rows() != k_.cols() || !k_.allFinite()) {
    throw ConfigError(fmt::format("specimen.stiffness: a {} × {} matrix; expected a finite "
                                  "square matrix in N/m, one row per actuator", k_.rows(),
                                  k_.cols()));
  }
}

void LinearCoupledLaw::Trial(std::span<const double> u, std::span<double> force) {
  const Eigen::Map<const Eigen::VectorXd> uv(u.data(), k_.cols());
  Eigen::Map<Eigen::VectorXd>(force.data(), k_.rows()) = k_ * uv;
}

std::unique_ptr<VectorRestoringForceLaw> LinearCoupledLaw::Clone() const {
  return std::make_unique<LinearCoupledLaw>(*this);
}

std::string LinearCoupledLaw::Describe() const {
  return fmt::format("coupled linear specimen ({} × {} stiffness)", k_.rows(), k_.cols());
}

}  // namespace hybridtest::constitutive
