#pragma once
// NumericalLoopback: the seed paper's "dummy" hybrid test as a TransferSystem. The physical
// specimen is replaced by a restoring-force law per actuator, evaluated exactly:
//   position_k = command_k,  force_k = law_k(command_k − p0_k),  lab_time = 0,
// for n ≥ 1 actuators (one law and one p0 each; n = 1 is the ordinary case).
// It speaks SI (m, N). Every Execute is a completed move, so the law is committed after each
// command (as the physical specimen would be). Same lifecycle as a real bench: Execute needs
// Activate(); after Hold() it refuses to move until Activate() again.
#include <memory>
#include <string>
#include <vector>

#include "hybridtest/constitutive/restoring_force_law.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer {

class NumericalLoopback final : public TransferSystem {
 public:
  // `law` must not be null (throws ConfigError). p0: zero-force position. Unit: [m].
  NumericalLoopback(std::unique_ptr<constitutive::RestoringForceLaw> law, double p0);
  // One law and one zero-force position [m] per actuator: at least one, as many p0 as laws,
  // none null (throws ConfigError naming the actuator).
  NumericalLoopback(std::vector<std::unique_ptr<constitutive::RestoringForceLaw>> laws,
                    std::vector<double> p0);

  void Activate() override { active_ = true; }
  int num_actuators() const override { return static_cast<int>(laws_.size()); }
  void Execute(std::span<const double> commands, std::span<Measurement> out) override;
  void Hold() noexcept override { active_ = false; }
  void Deactivate() override { active_ = false; }
  BenchUnits bench_units() const override { return BenchUnits{}; }
  std::string Describe() const override;

 private:
  std::vector<std::unique_ptr<constitutive::RestoringForceLaw>> laws_;
  std::vector<double> p0_;
  bool active_ = false;
};

}  // namespace hybridtest::transfer
