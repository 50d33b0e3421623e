#include "hybridtest/constitutive/linear_spring.h"

#include <cmath>

#include <fmt/format.h>

#include "hybridtest/common/error.h"

namespace hybridtest::constitutive {

LinearSpring::LinearSpring(double stiffness, std::string description)
    : stiffness_(stiffness), description_(std::move(description)) {
  if (!std::isfinite(stiffness)) {
    throw ConfigError(fmt::format(
        "linear spring: stiffness = {}: expected a finite stiffness in N/m", stiffness));
  }
}

std::unique_ptr<RestoringForceLaw> LinearSpring::Clone() const {
  return std::make_unique<LinearSpring>(*this);
}

std::string LinearSpring::Describe() const {
  if (!description_.empty()) return description_;
  return fmt::format("linear spring k={:g} N/m", stiffness_);
}

}  // namespace hybridtest::constitutive
