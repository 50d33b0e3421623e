// See law_block.h.
#include "hybridtest/substructures/law_block.h"

#include <fmt/core.h>

#include "hybridtest/common/error.h"

namespace hybridtest::substructures {

LawBlock::LawBlock(std::unique_ptr<constitutive::VectorRestoringForceLaw> law,
                   Eigen::MatrixXd transform)
    : law_(std::move(law)), t_(std::move(transform)) {
  if (!law_) throw ConfigError("law block: no law");
  if (t_.rows() != law_->num_axes() || t_.cols() < 1 || !t_.allFinite()) {
    throw ConfigError(fmt::format("law block: transform of {} × {} for a law of {} axes: expected "
                                  "one row per axis (actuator), one column per slot, finite",
                                  t_.rows(), t_.cols(), law_->num_axes()));
  }
  u_.resize(t_.rows());
  f_.resize(t_.rows());
}

LawBlock::LawBlock(std::unique_ptr<constitutive::VectorRestoringForceLaw> law,
                   std::shared_ptr<const ActuatorSetup> setup)
    : law_(std::move(law)), setup_(std::move(setup)) {
  if (!law_ || !setup_) throw ConfigError("law block: no law or no setup");
  if (setup_->num_actuators() != law_->num_axes()) {
    throw ConfigError(fmt::format("law block: a setup of {} actuators for a law of {} axes: "
                                  "expected one actuator per axis", setup_->num_actuators(),
                                  law_->num_axes()));
  }
  t_ = setup_->linearisation();
  u_.resize(t_.rows());
  f_.resize(t_.rows());
}

void LawBlock::Trial(std::span<const double> d, std::span<double> r,
                    const TrialContext& /*context*/) {
  const Eigen::Map<const Eigen::VectorXd> dv(d.data(), t_.cols());
  if (setup_) {
    setup_->CalcCommands(dv, u_);
    u_ -= setup_->p0();
  } else {
    u_ = t_ * dv;
  }
  law_->Trial({u_.data(), static_cast<std::size_t>(u_.size())},
              {f_.data(), static_cast<std::size_t>(f_.size())});
  if (setup_) {
    setup_->CalcSlotForces(dv, f_, Eigen::Map<Eigen::VectorXd>(r.data(), t_.cols()));
  } else {
    Eigen::Map<Eigen::VectorXd>(r.data(), t_.cols()) = t_.transpose() * f_;
  }
}

std::string LawBlock::Describe() const {
  return fmt::format("numerical block of {} slots{}: {}", num_slots(),
                     setup_ ? " through a " + setup_->Describe() : std::string(),
                     law_->Describe());
}

std::optional<Eigen::MatrixXd> LawBlock::initial_stiffness() const {
  return Eigen::MatrixXd(t_.transpose() * law_->initial_stiffness() * t_);
}

void LawBlock::RestoreState(const nlohmann::json& state) {
  if (!state.is_object() || !state.contains("law")) {
    throw Error(fmt::format("law block: cannot restore the state {}: expected {{\"law\": ...}}",
                            state.dump()));
  }
  law_->RestoreState(state.at("law"));
}

}  // namespace hybridtest::substructures
