// See slot_law.h.
#include "hybridtest/substructures/slot_law.h"

#include <fmt/core.h>

#include "hybridtest/substructures/physical_substructure.h"
#include "hybridtest/transfer/emulated_bench.h"

namespace hybridtest::substructures {

SlotLaw::SlotLaw(std::unique_ptr<constitutive::RestoringForceLaw> specimen,
                 const SetupTransform& setup, double bench_p0, double bench_offset)
    : specimen_(std::move(specimen)), setup_(setup), bench_p0_(bench_p0),
      bench_offset_(bench_offset) {}

double SlotLaw::Trial(double displacement) {
  const double deformation = setup_.CommandMetres(displacement) - bench_p0_;
  const double force = specimen_->Trial(deformation) + bench_offset_ - setup_.load_cell_zero;
  return setup_.RestoringForce(force);
}

double SlotLaw::initial_stiffness() const {
  return setup_.force_sign * setup_.force_scale * setup_.sign * setup_.scale *
         specimen_->initial_stiffness();
}

std::unique_ptr<constitutive::RestoringForceLaw> SlotLaw::Clone() const {
  return std::make_unique<SlotLaw>(specimen_->Clone(), setup_, bench_p0_, bench_offset_);
}

std::string SlotLaw::Describe() const {
  return fmt::format("{} through the setup (p0 {} m, sign {}, scale {}, force sign {}, force "
                     "scale {})", specimen_->Describe(), setup_.p0, setup_.sign, setup_.scale,
                     setup_.force_sign, setup_.force_scale);
}

std::unique_ptr<constitutive::RestoringForceLaw> EmulatedSlotLaw(const Substructure& substructure) {
  const auto* physical = dynamic_cast<const PhysicalSubstructure*>(&substructure);
  if (physical == nullptr) return nullptr;
  const auto* bench = dynamic_cast<const transfer::EmulatedBench*>(&physical->transfer());
  if (bench == nullptr) return nullptr;
  return std::make_unique<SlotLaw>(bench->config().specimen->Clone(), physical->setup(),
                                   bench->config().p0, bench->config().offset);
}

}  // namespace hybridtest::substructures
