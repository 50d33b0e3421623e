#include "hybridtest/integrators/explicit_runge_kutta.h"

#include <limits>
#include <utility>

#include <fmt/format.h>

#include "hybridtest/common/error.h"

namespace hybridtest::integrators {

ExplicitRungeKutta::ExplicitRungeKutta(ButcherTableau tableau, int state_size)
    : tableau_(std::move(tableau)) {
  ValidateTableau(tableau_, tableau_.name.empty() ? std::string_view("integrator")
                                                  : std::string_view(tableau_.name));
  if (state_size < 1) {
    throw ConfigError(fmt::format(
        "ExplicitRungeKutta('{}'): state_size = {}: expected at least one state entry",
        tableau_.name, state_size));
  }
  k_ = Eigen::MatrixXd::Constant(state_size, tableau_.stages(),
                                 std::numeric_limits<double>::quiet_NaN());
  x_i_ = Eigen::VectorXd::Zero(state_size);
}

void ExplicitRungeKutta::ThrowSizeMismatch(Eigen::Index given) const {
  throw Error(fmt::format(
      "ExplicitRungeKutta('{}')::Step: x has {} entries: expected the state size {} given to "
      "the constructor; build the stepper with the model's state size",
      tableau_.name, given, x_i_.size()));
}

}  // namespace hybridtest::integrators
