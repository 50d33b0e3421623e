#include "hybridtest/constitutive/bouc_wen.h"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "hybridtest/common/error.h"

namespace hybridtest::constitutive {
namespace {

void Require(bool ok, const char* name, double value, const char* expectation) {
  if (!ok) {
    throw ConfigError(
        fmt::format("bouc_wen: {} = {}: expected {}", name, value, expectation));
  }
}

}  // namespace

BoucWen::BoucWen(const Parameters& parameters) : p_(parameters) {
  Require(std::isfinite(p_.initial_stiffness) && p_.initial_stiffness > 0.0,
          "initial_stiffness", p_.initial_stiffness, "a positive stiffness in N/m");
  Require(p_.alpha >= 0.0 && p_.alpha <= 1.0, "alpha", p_.alpha,
          "a post-yield stiffness ratio between 0 and 1");
  Require(std::isfinite(p_.a) && p_.a > 0.0, "A", p_.a, "a positive number (1 is usual)");
  Require(std::isfinite(p_.n) && p_.n >= 1.0, "n", p_.n, "an exponent n >= 1");
  Require(std::isfinite(p_.beta) && std::isfinite(p_.gamma) && p_.beta + p_.gamma > 0.0,
          "beta + gamma", p_.beta + p_.gamma,
          "a positive sum, otherwise the hysteretic displacement is unbounded");
  Require(std::isfinite(p_.max_substep) && p_.max_substep >= 0.0, "max_substep",
          p_.max_substep, "a non-negative length in m (0 chooses z_u/200)");
  if (p_.max_substep == 0.0) p_.max_substep = ultimate_z() / 200.0;
}

BoucWen::Parameters BoucWen::FromYieldDisplacement(double initial_stiffness, double alpha,
                                                   double yield_displacement, double n) {
  Require(std::isfinite(yield_displacement) && yield_displacement > 0.0, "yield_displacement",
          yield_displacement, "a positive length in m");
  Require(std::isfinite(n) && n >= 1.0, "n", n, "an exponent n >= 1");
  Parameters p;
  p.initial_stiffness = initial_stiffness;
  p.alpha = alpha;
  p.a = 1.0;
  p.n = n;
  p.beta = 0.5 / std::pow(yield_displacement, n);
  p.gamma = p.beta;
  return p;
}

double BoucWen::ultimate_z() const { return std::pow(p_.a / (p_.beta + p_.gamma), 1.0 / p_.n); }

double BoucWen::CalcSlope(double z, double direction) const {
  const double sign = (direction * z > 0.0) ? 1.0 : ((direction * z < 0.0) ? -1.0 : 0.0);
  return p_.a - std::pow(std::abs(z), p_.n) * (p_.beta * sign + p_.gamma);
}

double BoucWen::CalcForce(double x, double z) const {
  return p_.alpha * p_.initial_stiffness * x + (1.0 - p_.alpha) * p_.initial_stiffness * z;
}

double BoucWen::Trial(double displacement) {
  // Integrate dz/dx from the committed state along the straight path to `displacement`.
  const double dx_total = displacement - x_committed_;
  double z = z_committed_;
  if (dx_total != 0.0 && std::isfinite(dx_total)) {
    const double direction = dx_total > 0.0 ? 1.0 : -1.0;
    const auto substeps =
        static_cast<long>(std::ceil(std::abs(dx_total) / p_.max_substep));
    const double h = dx_total / static_cast<double>(substeps);
    for (long i = 0; i < substeps; ++i) {
      // Classical RK4 in x; the direction of travel is fixed along the path.
      const double k1 = CalcSlope(z, direction);
      const double k2 = CalcSlope(z + 0.5 * h * k1, direction);
      const double k3 = CalcSlope(z + 0.5 * h * k2, direction);
      const double k4 = CalcSlope(z + h * k3, direction);
      z += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    }
  } else if (!std::isfinite(dx_total)) {
    z = std::numeric_limits<double>::quiet_NaN();
  }
  x_trial_ = displacement;
  z_trial_ = z;
  return CalcForce(displacement, z);
}

void BoucWen::Commit() {
  if (!std::isfinite(x_trial_) || !std::isfinite(z_trial_)) return;  // never commit garbage
  x_committed_ = x_trial_;
  z_committed_ = z_trial_;
}

nlohmann::json BoucWen::SaveState() const {
  return {{"law", "bouc_wen"}, {"x", x_committed_}, {"z", z_committed_}};
}

void BoucWen::RestoreState(const nlohmann::json& state) {
  if (!state.is_object() || state.value("law", "") != "bouc_wen" || !state.contains("x") ||
      !state.contains("z")) {
    throw Error(fmt::format("Bouc-Wen law: cannot restore the state {}: expected "
                            "{{\"law\": \"bouc_wen\", \"x\", \"z\"}}", state.dump()));
  }
  x_committed_ = x_trial_ = state.at("x").get<double>();
  z_committed_ = z_trial_ = state.at("z").get<double>();
}

std::unique_ptr<RestoringForceLaw> BoucWen::Clone() const {
  return std::make_unique<BoucWen>(*this);
}

std::string BoucWen::Describe() const {
  return fmt::format("Bouc-Wen k0={:g} N/m, alpha={:g}, A={:g}, beta={:g}, gamma={:g}, n={:g}",
                     p_.initial_stiffness, p_.alpha, p_.a, p_.beta, p_.gamma, p_.n);
}

}  // namespace hybridtest::constitutive
