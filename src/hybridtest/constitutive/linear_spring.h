#pragma once
// LinearSpring: r = k·d. Path independent; Commit() has nothing to store.
// Also the law of an elastic cantilever (see cantilever.h).
#include <memory>
#include <string>

#include "hybridtest/constitutive/restoring_force_law.h"

namespace hybridtest::constitutive {

class LinearSpring final : public RestoringForceLaw {
 public:
  // `stiffness` k. Unit: [N/m]. Must be finite (it may be zero or negative: a test of a
  // buckling specimen is legitimate). `description` replaces the default Describe() text.
  explicit LinearSpring(double stiffness, std::string description = "");

  double Trial(double displacement) override { return stiffness_ * displacement; }
  void Commit() override {}
  double initial_stiffness() const override { return stiffness_; }
  std::unique_ptr<RestoringForceLaw> Clone() const override;
  std::string Describe() const override;

  // Unit: [N/m].
  double stiffness() const { return stiffness_; }

 private:
  double stiffness_;
  std::string description_;
};

}  // namespace hybridtest::constitutive
