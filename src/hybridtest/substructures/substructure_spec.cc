// See substructure_spec.h.
#include "hybridtest/substructures/substructure_spec.h"

#include "hybridtest/substructures/slot_law.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "hybridtest/common/error.h"
#include "hybridtest/substructures/law_block.h"
#include "hybridtest/substructures/linear_block.h"
#include "hybridtest/transfer/emulated_bench.h"
#include "hybridtest/substructures/numerical_substructure.h"
#include "hybridtest/substructures/physical_substructure.h"

namespace hybridtest::substructures {

std::string ActuatorName(const std::string& name, int k, int n) {
  return n == 1 ? name : fmt::format("{}_a{}", name, k + 1);
}

std::vector<std::string> SubstructureSpec::ActuatorNames() const {
  const int n = num_actuators();
  std::vector<std::string> names;
  for (int k = 0; k < n; ++k) names.push_back(ActuatorName(slot, k, n));
  return names;
}

std::vector<transfer::SafetyLimits> SubstructureSpec::ActuatorLimits() const {
  if (!physical) return {};
  if (!physical->actuator_limits.empty()) return physical->actuator_limits;
  return std::vector<transfer::SafetyLimits>(static_cast<std::size_t>(num_actuators()),
                                             physical->limits);
}

std::unique_ptr<Substructure> SubstructureSpec::Build() const {
  if (custom) {
    auto built = custom();
    if (!built) throw ConfigError(fmt::format("slot {}: the custom factory made nothing", slot));
    if (built->is_physical() != custom_is_physical) {
      throw ConfigError(fmt::format("slot {}: the custom substructure is {}physical, but the "
                                    "spec says custom_is_physical = {}", slot,
                                    built->is_physical() ? "" : "not ", custom_is_physical));
    }
    return built;
  }
  if (physical) {
    if (!physical->transfer.make) {
      throw ConfigError(fmt::format("slot {}: a physical substructure needs a transfer system",
                                    slot));
    }
    // One class for every size: a linear setup of n actuators (the one-actuator
    // `setup: {p0, sign, scale, ...}` its case n = 1), or another geometry.
    std::unique_ptr<ActuatorSetup> setup;
    if (physical->actuator_setup && !physical->linear) {
      setup = physical->actuator_setup->Clone();
    } else {
      setup = std::make_unique<LinearActuatorSetup>(
          physical->linear ? *physical->linear : OneActuatorSetup(physical->setup));
    }
    const std::vector<transfer::SafetyLimits> limits = ActuatorLimits();
    auto built = std::make_unique<PhysicalSubstructure>(slot, physical->transfer.make(),
                                                         std::move(setup), limits);
    if (physical->slot_limits) {
      SlotLimits slot_limits = *physical->slot_limits;
      if (slot_limits.names.empty()) slot_limits.names = SlotNames();
      built->SetSlotLimits(std::move(slot_limits));
    }
    if (physical->safety_stiffness) built->SetSafetyStiffness(*physical->safety_stiffness);
    if (physical->initial_stiffness_matrix) {
      built->SetInitialStiffness(*physical->initial_stiffness_matrix);
    } else if (physical->initial_stiffness) {
      built->SetInitialStiffness(Eigen::MatrixXd::Constant(1, 1, *physical->initial_stiffness));
    }
    if (physical->stiffness_ramp) built->RequestStiffnessMeasurement(*physical->stiffness_ramp);
    return built;
  }
  if (stiffness) return std::make_unique<LinearBlock>(*stiffness);
  if (block_law && block_setup) return std::make_unique<LawBlock>(block_law->Clone(), block_setup);
  if (block_law) {
    const int n = block_law->num_axes();
    return std::make_unique<LawBlock>(
        block_law->Clone(), block_transform ? *block_transform : Eigen::MatrixXd::Identity(n, n));
  }
  if (!law) {
    throw ConfigError(fmt::format("slot {}: give a restoring-force law (numerical) or a "
                                  "physical spec", slot));
  }
  return std::make_unique<NumericalSubstructure>(law->Clone());
}

std::vector<std::vector<int>> SlotIndices(const std::vector<SubstructureSpec>& specs,
                                          const std::vector<std::string>& model_slots) {
  std::vector<std::vector<int>> out;
  std::vector<std::string> owner(model_slots.size());
  for (const auto& spec : specs) {
    auto& indices = out.emplace_back();
    for (const auto& name : spec.SlotNames()) {
      const auto it = std::find(model_slots.begin(), model_slots.end(), name);
      if (it == model_slots.end()) {
        throw ConfigError(fmt::format("substructure {}: the model has no slot '{}'", spec.slot,
                                      name));
      }
      const auto i = static_cast<std::size_t>(it - model_slots.begin());
      if (!owner[i].empty()) {
        throw ConfigError(fmt::format("slot {} is served by two substructures ({} and {}); give "
                                      "each slot to one", name, owner[i], spec.slot));
      }
      owner[i] = spec.slot;
      indices.push_back(static_cast<int>(i));
    }
  }
  for (std::size_t i = 0; i < model_slots.size(); ++i) {
    if (owner[i].empty()) {
      throw ConfigError(fmt::format("slot {} is served by no substructure; give it one",
                                    model_slots[i]));
    }
  }
  return out;
}

std::optional<SubstructureSpec> EmulatedBlockTwin(const Substructure& s) {
  const ActuatorSetup* setup_of = s.actuator_setup();
  if (setup_of == nullptr) return std::nullopt;
  // A coupled bench (its `actuators:` form) of as many actuators as the setup.
  const transfer::EmulatedBenchSpec* coupled = CoupledBench(s.transfer_system());
  if (coupled == nullptr || coupled->num_actuators() != setup_of->num_actuators()) {
    return std::nullopt;
  }
  const auto* bench = static_cast<const transfer::EmulatedBench*>(s.transfer_system());
  const ActuatorSetup& setup = *setup_of;
  for (int k = 0; k < setup.num_actuators(); ++k) {
    const auto& a = coupled->actuators[static_cast<std::size_t>(k)];
    if (std::abs(setup.p0()(k) - a.p0) > 1e-12 || setup.load_cell_zero()(k) != a.offset) {
      return std::nullopt;
    }
  }
  SubstructureSpec twin;
  twin.slot = s.Describe();
  twin.block_law = bench->specimen().Clone();
  if (setup.kind() == "linear") {
    twin.block_transform = setup.linearisation();
  } else {
    twin.block_setup = setup.Clone();
  }
  return twin;
}

SubstructureSpec NumericalSpec(std::string slot,
                               std::unique_ptr<constitutive::RestoringForceLaw> law) {
  SubstructureSpec spec;
  spec.slot = std::move(slot);
  spec.law = std::move(law);
  return spec;
}

}  // namespace hybridtest::substructures
