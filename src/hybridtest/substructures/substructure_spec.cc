// See substructure_spec.h.
#include "hybridtest/substructures/substructure_spec.h"

#include <fmt/core.h>

#include "hybridtest/common/error.h"
#include "hybridtest/substructures/numerical_substructure.h"
#include "hybridtest/substructures/physical_substructure.h"

namespace hybridtest::substructures {

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
    auto built = std::make_unique<PhysicalSubstructure>(slot, physical->transfer.make(),
                                                         physical->setup, physical->limits,
                                                         physical->safety_stiffness);
    if (physical->initial_stiffness) built->SetInitialStiffness(*physical->initial_stiffness);
    if (physical->stiffness_ramp) built->RequestStiffnessMeasurement(*physical->stiffness_ramp);
    return built;
  }
  if (!law) {
    throw ConfigError(fmt::format("slot {}: give a restoring-force law (numerical) or a "
                                  "physical spec", slot));
  }
  return std::make_unique<NumericalSubstructure>(law->Clone());
}

SubstructureSpec NumericalSpec(std::string slot,
                               std::unique_ptr<constitutive::RestoringForceLaw> law) {
  SubstructureSpec spec;
  spec.slot = std::move(slot);
  spec.law = std::move(law);
  return spec;
}

}  // namespace hybridtest::substructures
