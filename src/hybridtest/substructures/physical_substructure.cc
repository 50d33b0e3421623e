// See physical_substructure.h.
#include "hybridtest/substructures/physical_substructure.h"

#include <fmt/core.h>

#include <cmath>

#include "hybridtest/common/error.h"

namespace hybridtest::substructures {

void SetupTransform::Validate() const {
  if (std::abs(sign) != 1.0 || std::abs(force_sign) != 1.0) {
    throw ConfigError(fmt::format("setup: sign = {}, force_sign = {}: expected +1 or -1", sign,
                                  force_sign));
  }
  if (!(scale > 0.0) || !(force_scale > 0.0) || !std::isfinite(scale) ||
      !std::isfinite(force_scale)) {
    throw ConfigError(fmt::format("setup: scale = {}, force_scale = {}: expected positive finite "
                                  "factors", scale, force_scale));
  }
  if (!std::isfinite(p0) || !std::isfinite(load_cell_zero)) {
    throw ConfigError("setup: p0 and load_cell_zero must be finite");
  }
}

PhysicalSubstructure::PhysicalSubstructure(std::string name,
                                           std::unique_ptr<transfer::TransferSystem> transfer,
                                           SetupTransform setup, transfer::SafetyLimits limits,
                                           std::optional<double> initial_stiffness)
    : name_(std::move(name)), transfer_(std::move(transfer)), setup_(setup), safety_(limits) {
  if (!transfer_) throw Error("PhysicalSubstructure '" + name_ + "': no transfer system");
  setup_.Validate();
  safety_.SetStartPosition(setup_.p0);
  if (initial_stiffness) safety_.SetInitialStiffness(*initial_stiffness);
}

PhysicalSubstructure::~PhysicalSubstructure() {
  if (active_) Hold();
}

void PhysicalSubstructure::Activate() {
  transfer_->Activate();
  held_ = false;
  active_ = true;
}

double PhysicalSubstructure::Trial(double displacement, const TrialContext& ctx) {
  const transfer::BenchUnits units = transfer_->bench_units();
  const double command = setup_.CommandMetres(displacement);
  held_ = false;
  try {
    safety_.CheckCommand(command, ctx.step, ctx.stage);
    const transfer::Measurement m = transfer_->Execute(setup_.ToBench(command, units));
    ++evaluations_;
    const double position = setup_.PositionMetres(m.position, units);
    const double force = setup_.ForceNewtons(m.force, units);
    last_ = {command, position, force, m.lab_time};
    safety_.CheckMeasurement(command, position, force, ctx.step, ctx.stage);
    return setup_.RestoringForce(force);
  } catch (const transfer::SafetyStop&) {
    Hold();
    throw;
  } catch (const TransferError& e) {
    // Name where in the test the bench was lost; the actuator holds at its last command.
    Hold();
    throw TransferError(fmt::format("{}: {} (step {}, stage {}, t = {} s; the actuator holds at "
                                    "its last safe command {} m)", name_, e.what(), ctx.step,
                                    ctx.stage, ctx.t, safety_.has_safe_command()
                                                          ? safety_.last_safe_command()
                                                          : setup_.p0));
  } catch (...) {
    Hold();
    throw;
  }
}

void PhysicalSubstructure::Hold() noexcept {
  // One HOLD per failure: the trial, the runner's cleanup and the destructor may all ask.
  if (held_) return;
  held_ = true;
  transfer_->Hold();
}

void PhysicalSubstructure::Deactivate() {
  if (!active_) return;
  active_ = false;
  transfer_->Deactivate();
}

std::string PhysicalSubstructure::Describe() const {
  return fmt::format("physical ({}): {}, p0 = {} m", name_, transfer_->Describe(), setup_.p0);
}

}  // namespace hybridtest::substructures
