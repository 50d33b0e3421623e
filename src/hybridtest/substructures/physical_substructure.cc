// See physical_substructure.h.
#include "hybridtest/substructures/physical_substructure.h"

#include <fmt/core.h>

#include <algorithm>
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
    : name_(std::move(name)), transfer_(std::move(transfer)), setup_(setup), gate_(limits) {
  if (!transfer_) throw Error("PhysicalSubstructure '" + name_ + "': no transfer system");
  setup_.Validate();
  gate_.monitor().SetStartPosition(setup_.p0);
  if (initial_stiffness) gate_.monitor().SetInitialStiffness(*initial_stiffness);
  safety_stiffness_ = initial_stiffness;
}

std::optional<double> PhysicalSubstructure::initial_stiffness() const {
  if (k0_) return k0_;
  // The safety section's stiffness is force per actuator displacement; r per d differs by the
  // setup's signs and scales.
  if (safety_stiffness_) {
    return *safety_stiffness_ * setup_.sign * setup_.scale * setup_.force_sign * setup_.force_scale;
  }
  return std::nullopt;
}

void PhysicalSubstructure::SetInitialStiffness(double k0) {
  if (!std::isfinite(k0)) {
    throw ConfigError(fmt::format("{}: initial stiffness {} N/m: expected a finite value", name_, k0));
  }
  k0_ = k0;
  // The monitor predicts forces per actuator displacement from the start.
  const double per_actuator = k0 / (setup_.sign * setup_.scale * setup_.force_sign * setup_.force_scale);
  if (per_actuator > 0.0) gate_.monitor().SetInitialStiffness(per_actuator);
}

double PhysicalSubstructure::max_displacement_increment() const {
  return gate_.monitor().limits().max_increment / setup_.scale;
}

PhysicalSubstructure::StiffnessMeasurement PhysicalSubstructure::MeasureInitialStiffness(
    double amplitude) {
  if (!(amplitude > 0.0) || !std::isfinite(amplitude)) {
    throw ConfigError(fmt::format("{}: stiffness ramp amplitude {} m: expected a positive length",
                                  name_, amplitude));
  }
  // Moves of at most half the increment limit, at least 4 up and 4 down.
  const double step_limit = 0.5 * max_displacement_increment();
  const int steps = std::max(4, static_cast<int>(std::ceil(amplitude / step_limit)));
  StiffnessMeasurement out;
  out.amplitude = amplitude;
  for (int k = 1; k <= 2 * steps; ++k) {
    const int level = k <= steps ? k : 2 * steps - k;
    const double d = amplitude * static_cast<double>(level) / steps;
    // Labelled step −1: before the test's first step.
    out.samples.emplace_back(d, Trial(d, {-1, k, 0.0}));
  }
  double sdd = 0.0, sdr = 0.0, sd = 0.0, sr = 0.0;
  const double count = static_cast<double>(out.samples.size());
  for (const auto& [d, r] : out.samples) {
    sd += d;
    sr += r;
  }
  for (const auto& [d, r] : out.samples) {
    sdd += (d - sd / count) * (d - sd / count);
    sdr += (d - sd / count) * (r - sr / count);
  }
  out.k0 = sdr / sdd;
  if (!(out.k0 > 0.0) || !std::isfinite(out.k0)) {
    throw Error(fmt::format("{}: the stiffness ramp (0 → {} m → 0, {} samples) gave K0 = {} N/m; "
                            "expected a positive stiffness: check the specimen, the setup's signs "
                            "and the load cell, or give initial_stiffness in N/m",
                            name_, amplitude, out.samples.size(), out.k0));
  }
  SetInitialStiffness(out.k0);
  return out;
}

PhysicalSubstructure::~PhysicalSubstructure() {
  if (active_) Hold();
}

void PhysicalSubstructure::Activate() {
  transfer_->Activate();
  held_ = false;
  active_ = true;
}

void PhysicalSubstructure::GatedMoveTo(double command, transfer::MoveLabel label) {
  held_ = false;
  try {
    gate_.Move(*transfer_, command, label, setup_.load_cell_zero, move_);
  } catch (...) {
    if (move_.executed) {
      ++evaluations_;
      last_ = {command, move_.position, move_.force, move_.lab_time, move_.raw.force_reversals};
    }
    Hold();
    throw;
  }
  ++evaluations_;
  last_ = {command, move_.position, move_.force, move_.lab_time, move_.raw.force_reversals};
}

double PhysicalSubstructure::Trial(double displacement, const TrialContext& ctx) {
  const double command = setup_.CommandMetres(displacement);
  try {
    GatedMoveTo(command, {ctx.step, ctx.stage});
  } catch (const TransferError& e) {
    // Name where in the test the bench was lost; the actuator holds at its last command.
    throw TransferError(fmt::format("{}: {} (step {}, stage {}, t = {} s; the actuator holds at "
                                    "its last safe command {} m)", name_, e.what(), ctx.step,
                                    ctx.stage, ctx.t, gate_.monitor().has_safe_command()
                                                          ? gate_.monitor().last_safe_command()
                                                          : setup_.p0));
  }
  return setup_.RestoringForce(last_.force);
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
