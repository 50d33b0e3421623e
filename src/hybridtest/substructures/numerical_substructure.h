#pragma once
// A numerical substructure: a restoring-force law evaluated in the model's loop (a linear
// spring, k_b q_i for the paper's numerical blades; or Bouc–Wen for a hysteretic specimen).
#include <memory>

#include "hybridtest/constitutive/restoring_force_law.h"
#include "hybridtest/substructures/substructure.h"

namespace hybridtest::substructures {

class NumericalSubstructure final : public Substructure {
 public:
  explicit NumericalSubstructure(std::unique_ptr<constitutive::RestoringForceLaw> law);
  // One slot: r[0] = law(d[0]).
  void Trial(std::span<const double> d, std::span<double> r, const TrialContext& context) override;
  void Commit() override { law_->Commit(); }
  std::string Describe() const override;
  // The law's committed state ({"law": ...}).
  nlohmann::json SaveState() const override { return {{"law", law_->SaveState()}}; }
  void RestoreState(const nlohmann::json& state) override { law_->RestoreState(state.at("law")); }
  // From the law's initial tangent stiffness (1 × 1).
  std::optional<Eigen::MatrixXd> initial_stiffness() const override {
    return Eigen::MatrixXd::Constant(1, 1, law_->initial_stiffness());
  }

 private:
  std::unique_ptr<constitutive::RestoringForceLaw> law_;
};

}  // namespace hybridtest::substructures
