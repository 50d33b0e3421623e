#pragma once
// LawBlock: a numerical substructure of m slots whose restoring forces come from a coupled law
// of n axes (constitutive/vector_law.h) seen through a linear setup:
//
//   u = T d        (n)  [m]     the law's axes (actuator coordinates) from the slots
//   r = Tᵀ F(u)    (m)  [N]
//
// It is the numerical twin of a specimen on n actuators of an emulated bench whose setup is
// a = p0 + T d (the same p0 as the bench's, no load-cell zero): for a linear law F = K u it is
// the LinearBlock Tᵀ K T. A path-dependent law is trialled from its committed state and
// committed by Commit(). T is n × m with full column rank; T = I (n = m) uses the law as is.
//
// Seen through any setup (actuator_setup.h, e.g. the large-displacement RodSetup):
//
//   u = a(d) − p0  (n)  [m]     (ℓ(d) − L0 for rods)
//   r = J(d)ᵀ F(u) (m)  [N]
//
// the twin of a specimen on an emulated bench whose p0 is the setup's, no load-cell zero.
#include <memory>

#include "hybridtest/substructures/actuator_setup.h"

#include "hybridtest/constitutive/vector_law.h"
#include "hybridtest/substructures/substructure.h"

namespace hybridtest::substructures {

class LawBlock final : public Substructure {
 public:
  // Throws ConfigError unless T has one row per axis of the law and is finite.
  LawBlock(std::unique_ptr<constitutive::VectorRestoringForceLaw> law, Eigen::MatrixXd transform);
  // Throws ConfigError unless the setup has one actuator per axis of the law.
  LawBlock(std::unique_ptr<constitutive::VectorRestoringForceLaw> law,
           std::shared_ptr<const ActuatorSetup> setup);

  int num_slots() const override { return static_cast<int>(t_.cols()); }
  void Trial(std::span<const double> d, std::span<double> r, const TrialContext& context) override;
  void Commit() override { law_->Commit(); }
  std::string Describe() const override;
  // Tᵀ K0 T (m × m) [N/m], K0 the law's virgin tangent (T = T0 = J(0) through a setup).
  std::optional<Eigen::MatrixXd> initial_stiffness() const override;
  nlohmann::json SaveState() const override { return {{"law", law_->SaveState()}}; }
  void RestoreState(const nlohmann::json& state) override;

 private:
  std::unique_ptr<constitutive::VectorRestoringForceLaw> law_;
  Eigen::MatrixXd t_;  // T, or the setup's T0
  std::shared_ptr<const ActuatorSetup> setup_;  // null: the linear map T
  Eigen::VectorXd u_, f_;
};

}  // namespace hybridtest::substructures
