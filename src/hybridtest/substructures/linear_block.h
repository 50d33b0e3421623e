#pragma once
// LinearBlock: a numerical substructure of m slots, r = K d with a constant m × m stiffness
// K [N/m] (the numerical equivalent of a linear specimen on n actuators: Tᵀ K_a T).
#include <fmt/core.h>

#include <string>

#include "hybridtest/common/error.h"
#include "hybridtest/substructures/substructure.h"

namespace hybridtest::substructures {

class LinearBlock final : public Substructure {
 public:
  // Throws ConfigError unless K is square and finite.
  explicit LinearBlock(Eigen::MatrixXd stiffness) : k_(std::move(stiffness)) {
    if (k_.rows() < 1 || k_.rows() != k_.cols() || !k_.allFinite()) {
      throw ConfigError(fmt::format("law.stiffness: a {} × {} matrix; expected a finite square "
                                    "matrix in N/m, one row per slot", k_.rows(), k_.cols()));
    }
  }
  int num_slots() const override { return static_cast<int>(k_.rows()); }
  void Trial(std::span<const double> d, std::span<double> r,
             const TrialContext& /*context*/) override {
    const Eigen::Map<const Eigen::VectorXd> dv(d.data(), static_cast<Eigen::Index>(d.size()));
    Eigen::Map<Eigen::VectorXd>(r.data(), static_cast<Eigen::Index>(r.size())) = k_ * dv;
  }
  void Commit() override {}
  std::string Describe() const override {
    return fmt::format("linear block of {} slots", k_.rows());
  }
  std::optional<Eigen::MatrixXd> initial_stiffness() const override { return k_; }

 private:
  Eigen::MatrixXd k_;
};

}  // namespace hybridtest::substructures
