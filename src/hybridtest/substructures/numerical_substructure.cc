// See numerical_substructure.h.
#include "hybridtest/substructures/numerical_substructure.h"

#include "hybridtest/common/error.h"

namespace hybridtest::substructures {

NumericalSubstructure::NumericalSubstructure(std::unique_ptr<constitutive::RestoringForceLaw> law)
    : law_(std::move(law)) {
  if (!law_) throw Error("NumericalSubstructure: no restoring-force law given");
}

double NumericalSubstructure::Trial(double displacement, const TrialContext& /*context*/) {
  return law_->Trial(displacement);
}

std::string NumericalSubstructure::Describe() const { return "numerical: " + law_->Describe(); }

}  // namespace hybridtest::substructures
