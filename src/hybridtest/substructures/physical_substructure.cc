// See physical_substructure.h. The checkpoint, the resume and the K0 ramps are in
// physical_substructure_state.cc, physical_resume.cc and physical_stiffness.cc.
#include "hybridtest/substructures/physical_substructure.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "hybridtest/common/error.h"

namespace hybridtest::substructures {

PhysicalSubstructure::PhysicalSubstructure(std::string name,
                                           std::unique_ptr<transfer::TransferSystem> transfer,
                                           std::unique_ptr<ActuatorSetup> setup,
                                           std::vector<transfer::SafetyLimits> limits)
    : name_(std::move(name)), transfer_(std::move(transfer)), setup_(std::move(setup)),
      gate_(limits) {
  if (!transfer_) throw Error("PhysicalSubstructure '" + name_ + "': no transfer system");
  if (!setup_) throw Error("PhysicalSubstructure '" + name_ + "': no setup");
  const int n = setup_->num_actuators();
  if (gate_.size() != n) {
    throw ConfigError(fmt::format("{}: the setup has {} actuators and {} sets of safety limits "
                                  "were given", name_, n, gate_.size()));
  }
  for (int k = 0; k < n; ++k) gate_.monitor(k).SetStartPosition(setup_->p0()(k));
  last_.resize(static_cast<std::size_t>(n));
  commands_.resize(static_cast<std::size_t>(n));
  zeros_.assign(setup_->load_cell_zero().data(), setup_->load_cell_zero().data() + n);
  f_.resize(n);
}

PhysicalSubstructure::PhysicalSubstructure(std::string name,
                                           std::unique_ptr<transfer::TransferSystem> transfer,
                                           LinearSetup setup,
                                           std::vector<transfer::SafetyLimits> limits)
    : PhysicalSubstructure(std::move(name), std::move(transfer),
                           std::make_unique<LinearActuatorSetup>(std::move(setup)),
                           std::move(limits)) {}

PhysicalSubstructure::PhysicalSubstructure(std::string name,
                                           std::unique_ptr<transfer::TransferSystem> transfer,
                                           const SetupTransform& setup,
                                           transfer::SafetyLimits limits,
                                           std::optional<double> safety_stiffness)
    : PhysicalSubstructure(std::move(name), std::move(transfer),
                           std::make_unique<LinearActuatorSetup>(OneActuatorSetup(setup)),
                           std::vector<transfer::SafetyLimits>{limits}) {
  if (safety_stiffness) SetSafetyStiffness(*safety_stiffness);
}

PhysicalSubstructure::~PhysicalSubstructure() {
  if (active_) Hold();
}

void PhysicalSubstructure::SetSlotLimits(SlotLimits limits) {
  const auto m = static_cast<Eigen::Index>(num_slots());
  auto check = [&](const Eigen::VectorXd& v, const char* key, const char* unit) {
    if (v.size() != m || !(v.array() > 0.0).all() || v.hasNaN()) {
      throw ConfigError(fmt::format("{}: safety.slots.{} has {} values: expected one positive "
                                    "limit in {} per slot ({})", name_, key, v.size(), unit, m));
    }
  };
  if (limits.max_displacement.size() == 0) {
    limits.max_displacement = Eigen::VectorXd::Constant(m, std::numeric_limits<double>::infinity());
  }
  if (limits.max_force.size() == 0) {
    limits.max_force = Eigen::VectorXd::Constant(m, std::numeric_limits<double>::infinity());
  }
  check(limits.max_displacement, "max_displacement", "m");
  check(limits.max_force, "max_force", "N");
  if (limits.names.size() != static_cast<std::size_t>(m)) {
    limits.names.clear();
    for (Eigen::Index i = 0; i < m; ++i) limits.names.push_back(fmt::format("{}", i + 1));
  }
  slot_limits_ = std::move(limits);
}

void PhysicalSubstructure::CheckSlotDisplacements(std::span<const double> d,
                                                  const TrialContext& ctx) {
  if (!slot_limits_) return;
  for (std::size_t i = 0; i < d.size(); ++i) {
    const double limit = slot_limits_->max_displacement(static_cast<Eigen::Index>(i));
    if (std::abs(d[i]) <= limit) continue;  // NaN falls through: refused
    Hold();
    throw transfer::SafetyStop(
        "slot_max_displacement", d[i], limit, ctx.step, ctx.stage, gate_.monitor(0).history(),
        fmt::format("{}: slot {} displacement {} m is beyond its safety.slots.max_displacement "
                    "{} m (step {}, stage {}, t = {} s); refused before any actuator moved, "
                    "every actuator holds", name_, slot_limits_->names[i], d[i], limit, ctx.step,
                    ctx.stage, ctx.t));
  }
}

void PhysicalSubstructure::CheckSlotForces(std::span<const double> r, const TrialContext& ctx) {
  if (!slot_limits_) return;
  for (std::size_t i = 0; i < r.size(); ++i) {
    const double limit = slot_limits_->max_force(static_cast<Eigen::Index>(i));
    if (std::abs(r[i]) <= limit) continue;
    Hold();
    throw transfer::SafetyStop(
        "slot_max_force", r[i], limit, ctx.step, ctx.stage, gate_.monitor(0).history(),
        fmt::format("{}: slot {} restoring force {} N is beyond its safety.slots.max_force {} N "
                    "(step {}, stage {}, t = {} s); every actuator holds", name_,
                    slot_limits_->names[i], r[i], limit, ctx.step, ctx.stage, ctx.t));
  }
}

void PhysicalSubstructure::Activate() {
  transfer_->Activate();
  held_ = false;
  active_ = true;
  // A remote bench says how many actuators it has once connected.
  if (transfer_->num_actuators() != num_actuators()) {
    Hold();
    throw ConfigError(fmt::format("{}: the setup has {} actuators (rows of T, values of p0), the "
                                  "transfer system ({}) moves {}: give one row of T and one p0 "
                                  "per actuator", name_, num_actuators(), transfer_->Describe(),
                                  transfer_->num_actuators()));
  }
}

void PhysicalSubstructure::MoveAll(const std::vector<double>& commands,
                                   transfer::MoveLabel label) {
  held_ = false;
  auto record = [&] {
    if (moves_.empty() || !moves_[0].executed) return;
    ++evaluations_;
    for (std::size_t k = 0; k < last_.size(); ++k) {
      last_[k] = {commands[k], moves_[k].position, moves_[k].force, moves_[k].lab_time,
                  moves_[k].raw.force_reversals};
    }
  };
  try {
    gate_.Move(*transfer_, commands, label, zeros_, moves_);
  } catch (...) {
    record();
    Hold();
    throw;
  }
  record();
}

void PhysicalSubstructure::Trial(std::span<const double> d, std::span<double> r,
                                 const TrialContext& ctx) {
  const Eigen::Map<const Eigen::VectorXd> dv(d.data(), static_cast<Eigen::Index>(d.size()));
  CheckSlotDisplacements(d, ctx);
  try {
    setup_->CalcCommands(dv, Eigen::Map<Eigen::VectorXd>(commands_.data(), num_actuators()));
  } catch (const Error& e) {
    Hold();
    throw Error(fmt::format("{}: {} (step {}, stage {}, t = {} s; every actuator holds)", name_,
                            e.what(), ctx.step, ctx.stage, ctx.t));
  }
  try {
    MoveAll(commands_, {ctx.step, ctx.stage});
  } catch (const TransferError& e) {
    // Name where in the test the bench was lost; every actuator holds at its last command.
    // In m, and in the bench's length unit where that is another (the driver's messages are).
    const transfer::BenchUnits units = transfer_->bench_units();
    std::string held, held_in_bench;
    for (int k = 0; k < num_actuators(); ++k) {
      const auto& monitor = gate_.monitor(k);
      const double at = monitor.has_safe_command() ? monitor.last_safe_command() : setup_->p0()(k);
      held += fmt::format("{}{:.9g}", k > 0 ? ", " : "", at);
      held_in_bench += fmt::format("{}{:.9g}", k > 0 ? ", " : "",
                                   at / units.metres_per_length_unit);
    }
    const std::string in_bench_unit =
        units.metres_per_length_unit == 1.0
            ? std::string()
            : fmt::format(" = {} {}", held_in_bench, units.length_name);
    throw TransferError(fmt::format("{}: {} (step {}, stage {}, t = {} s; every actuator holds "
                                    "at its last safe command: {} m{})", name_, e.what(),
                                    ctx.step, ctx.stage, ctx.t, held, in_bench_unit));
  }
  for (int k = 0; k < f_.size(); ++k) f_(k) = last_[static_cast<std::size_t>(k)].force;
  setup_->CalcSlotForces(dv, f_, Eigen::Map<Eigen::VectorXd>(r.data(),
                                                             static_cast<Eigen::Index>(r.size())));
  CheckSlotForces(r, ctx);
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
  if (num_actuators() == 1 && num_slots() == 1) {
    return fmt::format("physical ({}): {}, p0 = {} m", name_, transfer_->Describe(),
                       setup_->p0()(0));
  }
  return fmt::format("physical ({}; {} slots, {} actuators, {}): {}", name_, num_slots(),
                     num_actuators(), setup_->Describe(), transfer_->Describe());
}

double PhysicalSubstructure::max_displacement_increment() const {
  double inc = std::numeric_limits<double>::infinity();
  for (int k = 0; k < num_actuators(); ++k) {
    const double row = setup_->CommandStepBound(k);
    if (row > 0.0) inc = std::min(inc, gate_.monitor(k).limits().max_increment / row);
  }
  return inc;
}

}  // namespace hybridtest::substructures
