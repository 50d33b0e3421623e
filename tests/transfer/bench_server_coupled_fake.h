#pragma once
// A bench of two actuators on one coupled linear specimen, for the servers' coupled-prediction
// tests: f = K (a − p0) with p0 = 0, positions exactly the commands, in m and N. It checks
// nothing itself and counts the command vectors it executed (thread-safe).
#include <Eigen/Core>

#include <mutex>
#include <span>
#include <string>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer::testing {

// Actuator 1 is stiff, actuator 2 soft, and a move of actuator 2 loads actuator 1 through
// K12: positive definite (K12² < K11 K22). Unit: [N/m].
inline Eigen::Matrix2d CoupledStiffness() {
  Eigen::Matrix2d k;
  k << 20000.0, 5000.0, 5000.0, 2000.0;
  return k;
}

class CoupledFakeBench final : public TransferSystem {
 public:
  void Activate() override {}
  int num_actuators() const override { return 2; }
  void Execute(std::span<const double> commands, std::span<Measurement> out) override {
    std::lock_guard lock(mutex_);
    ++executed_;
    const Eigen::Vector2d a(commands[0], commands[1]);
    const Eigen::Vector2d f = CoupledStiffness() * a;
    for (int k = 0; k < 2; ++k) out[static_cast<std::size_t>(k)] = {a(k), f(k), 1.0 * executed_};
  }
  void Hold() noexcept override {}
  void Deactivate() override {}
  BenchUnits bench_units() const override { return BenchUnits{1.0, 1.0, "m", "N"}; }
  std::string Describe() const override { return "fake coupled bench (2 actuators)"; }

  int executed() const {
    std::lock_guard lock(mutex_);
    return executed_;
  }

 private:
  mutable std::mutex mutex_;
  int executed_ = 0;
};

}  // namespace hybridtest::transfer::testing
