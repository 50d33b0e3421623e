// See bouc_wen_biaxial.h.
#include "hybridtest/constitutive/bouc_wen_biaxial.h"

#include <fmt/format.h>

#include <cmath>
#include <limits>

#include "hybridtest/common/error.h"

namespace hybridtest::constitutive {
namespace {

void Require(bool ok, const std::string& name, double value, const char* expectation) {
  if (!ok) {
    throw ConfigError(fmt::format("bouc_wen_biaxial: {} = {}: expected {}", name, value,
                                  expectation));
  }
}

}  // namespace

BoucWenBiaxial::BoucWenBiaxial(const Parameters& parameters) : p_(parameters) {
  const std::size_t n = p_.initial_stiffness.size();
  if (n == 0 || p_.yield_displacement.size() != n) {
    throw ConfigError(fmt::format("bouc_wen_biaxial: {} stiffnesses and {} yield displacements: "
                                  "expected one of each per axis (actuator)", n,
                                  p_.yield_displacement.size()));
  }
  for (std::size_t i = 0; i < n; ++i) {
    Require(std::isfinite(p_.initial_stiffness[i]) && p_.initial_stiffness[i] > 0.0,
            fmt::format("initial_stiffness[{}]", i), p_.initial_stiffness[i],
            "a positive stiffness in N/m");
    Require(std::isfinite(p_.yield_displacement[i]) && p_.yield_displacement[i] > 0.0,
            fmt::format("yield_displacement[{}]", i), p_.yield_displacement[i],
            "a positive length in m");
  }
  Require(p_.alpha >= 0.0 && p_.alpha <= 1.0, "alpha", p_.alpha,
          "a post-yield stiffness ratio between 0 and 1");
  Require(std::isfinite(p_.a) && p_.a > 0.0, "A", p_.a, "a positive number (1 is usual)");
  Require(std::isfinite(p_.beta) && std::isfinite(p_.gamma) && p_.beta + p_.gamma > 0.0,
          "beta + gamma", p_.beta + p_.gamma,
          "a positive sum, otherwise the hysteretic vector is unbounded");
  Require(std::isfinite(p_.max_substep) && p_.max_substep > 0.0, "max_substep", p_.max_substep,
          "a positive step in u / Y (1/200 is the default)");
  const auto ni = static_cast<Eigen::Index>(n);
  u_committed_ = z_committed_ = u_trial_ = z_trial_ = Eigen::VectorXd::Zero(ni);
}

Eigen::VectorXd BoucWenBiaxial::Slope(const Eigen::VectorXd& z, const Eigen::VectorXd& dv) const {
  const double hysteretic = p_.beta * (dv.cwiseProduct(z)).cwiseAbs().sum() + p_.gamma * dv.dot(z);
  return p_.a * dv - hysteretic * z;
}

void BoucWenBiaxial::Trial(std::span<const double> u, std::span<double> force) {
  const Eigen::Index n = num_axes();
  const Eigen::Map<const Eigen::VectorXd> uv(u.data(), n);
  Eigen::VectorXd dv(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    dv(i) = (uv(i) - u_committed_(i)) / p_.yield_displacement[static_cast<std::size_t>(i)];
  }
  Eigen::VectorXd z = z_committed_;
  const double length = dv.cwiseAbs().maxCoeff();
  if (!std::isfinite(length)) {
    z.setConstant(std::numeric_limits<double>::quiet_NaN());
  } else if (length > 0.0) {
    // Classical RK4 in the path parameter s ∈ [0, 1]; the direction dv is fixed along the path.
    const auto substeps = static_cast<long>(std::ceil(length / p_.max_substep));
    const double h = 1.0 / static_cast<double>(substeps);
    for (long s = 0; s < substeps; ++s) {
      const Eigen::VectorXd k1 = Slope(z, dv);
      const Eigen::VectorXd k2 = Slope(z + 0.5 * h * k1, dv);
      const Eigen::VectorXd k3 = Slope(z + 0.5 * h * k2, dv);
      const Eigen::VectorXd k4 = Slope(z + h * k3, dv);
      z += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    }
  }
  u_trial_ = uv;
  z_trial_ = z;
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto si = static_cast<std::size_t>(i);
    const double k = p_.initial_stiffness[si];
    force[si] = p_.alpha * k * uv(i) + (1.0 - p_.alpha) * k * p_.yield_displacement[si] * z(i);
  }
}

void BoucWenBiaxial::Commit() {
  if (!u_trial_.allFinite() || !z_trial_.allFinite()) return;  // never commit garbage
  u_committed_ = u_trial_;
  z_committed_ = z_trial_;
}

Eigen::MatrixXd BoucWenBiaxial::initial_stiffness() const {
  Eigen::VectorXd d(num_axes());
  for (Eigen::Index i = 0; i < d.size(); ++i) {
    d(i) = p_.initial_stiffness[static_cast<std::size_t>(i)] * (p_.alpha + (1.0 - p_.alpha) * p_.a);
  }
  return d.asDiagonal();
}

std::unique_ptr<VectorRestoringForceLaw> BoucWenBiaxial::Clone() const {
  return std::make_unique<BoucWenBiaxial>(*this);
}

std::string BoucWenBiaxial::Describe() const {
  std::string k, y;
  for (std::size_t i = 0; i < p_.initial_stiffness.size(); ++i) {
    k += fmt::format("{}{:g}", i ? ", " : "", p_.initial_stiffness[i]);
    y += fmt::format("{}{:g}", i ? ", " : "", p_.yield_displacement[i] * 1e3);
  }
  return fmt::format("biaxial Bouc-Wen (Park-Wen-Ang) k=[{}] N/m, Y=[{}] mm, alpha={:g}, A={:g}, "
                     "beta={:g}, gamma={:g}", k, y, p_.alpha, p_.a, p_.beta, p_.gamma);
}

nlohmann::json BoucWenBiaxial::SaveState() const {
  return {{"law", "bouc_wen_biaxial"},
          {"u", std::vector<double>(u_committed_.data(), u_committed_.data() + u_committed_.size())},
          {"z", std::vector<double>(z_committed_.data(), z_committed_.data() + z_committed_.size())}};
}

void BoucWenBiaxial::RestoreState(const nlohmann::json& state) {
  const auto n = static_cast<std::size_t>(num_axes());
  if (!state.is_object() || state.value("law", "") != "bouc_wen_biaxial" ||
      !state.contains("u") || !state.contains("z") || !state.at("u").is_array() ||
      !state.at("z").is_array() || state.at("u").size() != n || state.at("z").size() != n) {
    throw Error(fmt::format("biaxial Bouc-Wen law: cannot restore the state {}: expected "
                            "{{\"law\": \"bouc_wen_biaxial\", \"u\", \"z\"}} with {} values each",
                            state.dump(), n));
  }
  for (std::size_t i = 0; i < n; ++i) {
    const auto ii = static_cast<Eigen::Index>(i);
    u_committed_(ii) = u_trial_(ii) = state.at("u")[i].get<double>();
    z_committed_(ii) = z_trial_(ii) = state.at("z")[i].get<double>();
  }
}

}  // namespace hybridtest::constitutive
