// See numerical_substructure.h.
#include "hybridtest/substructures/numerical_substructure.h"

#include "hybridtest/common/error.h"

namespace hybridtest::substructures {

NumericalSubstructure::NumericalSubstructure(std::unique_ptr<constitutive::RestoringForceLaw> law)
    : law_(std::move(law)) {
  if (!law_) throw Error("NumericalSubstructure: no restoring-force law given");
}

void NumericalSubstructure::Trial(std::span<const double> d, std::span<double> r,
                                  const TrialContext& /*context*/) {
  r[0] = law_->Trial(d[0]);
}

std::string NumericalSubstructure::Describe() const { return "numerical: " + law_->Describe(); }

}  // namespace hybridtest::substructures
