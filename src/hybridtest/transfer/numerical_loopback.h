#pragma once
// NumericalLoopback: the seed paper's "dummy" hybrid test as a TransferSystem. The physical
// specimen is replaced by a restoring-force law evaluated exactly:
//   position = command,  force = law(command − p0),  lab_time = 0.
// It speaks SI (m, N). Every Execute is a completed move, so the law is committed after each
// command (as the physical specimen would be). Same lifecycle as a real bench: Execute needs
// Activate(); after Hold() it refuses to move until Activate() again.
#include <memory>
#include <string>

#include "hybridtest/constitutive/restoring_force_law.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer {

class NumericalLoopback final : public TransferSystem {
 public:
  // `law` must not be null (throws ConfigError). p0: zero-force position. Unit: [m].
  NumericalLoopback(std::unique_ptr<constitutive::RestoringForceLaw> law, double p0);

  void Activate() override { active_ = true; }
  int num_actuators() const override { return 1; }
  void Execute(std::span<const double> commands, std::span<Measurement> out) override;
  void Hold() noexcept override { active_ = false; }
  void Deactivate() override { active_ = false; }
  BenchUnits bench_units() const override { return BenchUnits{}; }
  std::string Describe() const override;

 private:
  std::unique_ptr<constitutive::RestoringForceLaw> law_;
  double p0_;
  bool active_ = false;
};

}  // namespace hybridtest::transfer
