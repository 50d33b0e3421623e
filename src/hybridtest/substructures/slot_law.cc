// See slot_law.h.
#include "hybridtest/substructures/slot_law.h"

#include <fmt/core.h>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/emulated_bench.h"

namespace hybridtest::substructures {

SlotLaw::SlotLaw(std::unique_ptr<constitutive::RestoringForceLaw> specimen,
                 std::shared_ptr<const ActuatorSetup> setup, double bench_p0, double bench_offset)
    : specimen_(std::move(specimen)), setup_(std::move(setup)), bench_p0_(bench_p0),
      bench_offset_(bench_offset), d_(1), a_(1), f_(1), r_(1) {
  if (!specimen_ || !setup_ || setup_->num_actuators() != 1 || setup_->num_slots() != 1) {
    throw ConfigError("SlotLaw: expected a specimen law and a setup of one actuator and one slot");
  }
}

double SlotLaw::Trial(double displacement) {
  d_(0) = displacement;
  setup_->CalcCommands(d_, a_);
  const double deformation = a_(0) - bench_p0_;
  f_(0) = specimen_->Trial(deformation) + bench_offset_ - setup_->load_cell_zero()(0);
  setup_->CalcSlotForces(d_, f_, r_);
  return r_(0);
}

double SlotLaw::initial_stiffness() const {
  return setup_->SlotStiffness(Eigen::MatrixXd::Constant(1, 1, specimen_->initial_stiffness()))(0, 0);
}

std::unique_ptr<constitutive::RestoringForceLaw> SlotLaw::Clone() const {
  return std::make_unique<SlotLaw>(specimen_->Clone(), setup_, bench_p0_, bench_offset_);
}

std::string SlotLaw::Describe() const {
  return fmt::format("{} through the {}", specimen_->Describe(), setup_->Describe());
}

const transfer::EmulatedBenchConfig* OneActuatorBench(const transfer::TransferSystem* transfer) {
  // The builders' one look at a concrete transfer type: plan's twin needs the emulated
  // specimen's own law, which no TransferSystem exposes.
  const auto* bench = dynamic_cast<const transfer::EmulatedBench*>(transfer);
  if (bench == nullptr || bench->spec().coupled_safety || bench->num_actuators() != 1) {
    return nullptr;
  }
  const transfer::EmulatedBenchConfig& config = bench->spec().actuators[0];
  return config.specimen ? &config : nullptr;
}

const transfer::EmulatedBenchSpec* CoupledBench(const transfer::TransferSystem* transfer) {
  const auto* bench = dynamic_cast<const transfer::EmulatedBench*>(transfer);
  return bench != nullptr && bench->spec().coupled_safety ? &bench->spec() : nullptr;
}

std::unique_ptr<constitutive::RestoringForceLaw> EmulatedSlotLaw(const Substructure& substructure) {
  const ActuatorSetup* setup = substructure.actuator_setup();
  if (setup == nullptr || setup->num_actuators() != 1 || setup->num_slots() != 1) return nullptr;
  const transfer::EmulatedBenchConfig* bench = OneActuatorBench(substructure.transfer_system());
  if (bench == nullptr) return nullptr;
  return std::make_unique<SlotLaw>(bench->specimen->Clone(),
                                   std::shared_ptr<const ActuatorSetup>(setup->Clone()),
                                   bench->p0, bench->offset);
}

}  // namespace hybridtest::substructures
