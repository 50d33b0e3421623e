// See twin.h.
#include "hybridtest/substructures/twin.h"

#include <fmt/core.h>

#include <cmath>

#include "hybridtest/common/error.h"
#include "hybridtest/constitutive/linear_spring.h"
#include "hybridtest/substructures/actuator_setup.h"
#include "hybridtest/substructures/slot_law.h"
#include "hybridtest/transfer/emulated_bench.h"

namespace hybridtest::substructures {

// The emulated specimen's law behind a physical substructure of one actuator and one slot, as
// a numerical one: the bench's law itself for the identity setup, else that law seen through
// the setup (substructures/slot_law.h); a linear spring of K0 where the bench is not emulated.
std::shared_ptr<const constitutive::RestoringForceLaw> TwinLaw(const Substructure& s,
                                                               const std::string& slot) {
  const ActuatorSetup* setup = s.actuator_setup();
  if (setup == nullptr) return nullptr;
  const transfer::EmulatedBenchConfig* one = OneActuatorBench(s.transfer_system());
  if (one != nullptr && setup->is_identity() && std::abs(setup->p0()(0) - one->p0) < 1e-12) {
    return one->specimen->Clone();
  }
  // Any other setup (a lever, flipped signs, a preload, a load-cell zero) or law: the
  // emulated specimen's law seen at the slot, through the setup.
  if (auto law = EmulatedSlotLaw(s)) return law;
  const auto k0 = s.initial_stiffness();
  if (!k0) {
    throw ConfigError(fmt::format("plan: slot {} has no emulated specimen law that the reference "
                                  "can use and no initial_stiffness; give "
                                  "substructures.{}.initial_stiffness in N/m", slot, slot));
  }
  return std::make_unique<constitutive::LinearSpring>((*k0)(0, 0), "plan reference (K0)");
}

// The numerical twin of a specimen on several actuators of an emulated bench: T0ᵀ K T0, with
// T0 = J(0) the setup's linearisation (EmulatedBlockTwin, asked first, sees the geometry).
std::optional<Eigen::MatrixXd> TwinStiffness(const Substructure& s, const std::string& name) {
  const ActuatorSetup* setup_of = s.actuator_setup();
  if (setup_of == nullptr) return std::nullopt;
  const ActuatorSetup& setup = *setup_of;
  const transfer::EmulatedBenchSpec* coupled = CoupledBench(s.transfer_system());
  if (coupled != nullptr && coupled->num_actuators() == setup.num_actuators()) {
    for (int k = 0; k < setup.num_actuators(); ++k) {
      const transfer::EmulatedBenchConfig& actuator =
          coupled->actuators[static_cast<std::size_t>(k)];
      if (std::abs(setup.p0()(k) - actuator.p0) > 1e-12 ||
          setup.load_cell_zero()(k) != actuator.offset) {
        throw ConfigError(fmt::format("plan: substructure {}: the setup's p0 and load-cell zero "
                                      "of actuator {} differ from the bench's; the reference "
                                      "needs them equal", name, k + 1));
      }
    }
    return setup.SlotStiffness(coupled->stiffness);
  }
  // One actuator and one slot: TwinLaw's law.
  if (setup.num_actuators() == 1 && setup.num_slots() == 1) return std::nullopt;
  if (auto k0 = s.initial_stiffness()) return k0;
  throw ConfigError(fmt::format("plan: substructure {} has no emulated specimen and no "
                                "initial_stiffness; give it as a matrix in N/m", name));
}

std::optional<TransferSpec> ReseededTransfer(const TransferSpec& spec, unsigned long seed) {
  if (!spec.make) return std::nullopt;
  const auto built = spec.make();
  // A bench of one actuator with a noisy load cell: the same bench with another seed. (A
  // coupled bench of several actuators keeps its seeds: plan's reference runs it as given.)
  const transfer::EmulatedBenchConfig* one = OneActuatorBench(built.get());
  if (one == nullptr || !(one->noise_std > 0.0)) return std::nullopt;
  transfer::EmulatedBenchConfig config = *one;
  config.seed = seed;
  return TransferSpec{spec.type, [config] {
                        return std::unique_ptr<transfer::TransferSystem>(
                            transfer::MakeEmulatedBench(config));
                      }};
}

}  // namespace hybridtest::substructures
