#pragma once
// Test double: a TransferSystem that records every call and answers like a linear spring in
// its own bench units. Shared state lives in a Log the test keeps after the transfer system
// has been moved into a PhysicalSubstructure.
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::substructures::testing {

struct TransferLog {
  std::vector<double> executed;   // every command Execute received [bench length unit]
  int activations = 0;
  int holds = 0;
  int deactivations = 0;
  // Fault for the Execute call with this 0-based index.
  std::optional<long> throw_transfer_error_at;
  std::optional<long> nan_force_at;
};

// position = command; force = stiffness · (command − p0) [bench units].
class RecordingTransfer final : public transfer::TransferSystem {
 public:
  RecordingTransfer(std::shared_ptr<TransferLog> log, transfer::BenchUnits units, double stiffness,
                    double p0)
      : log_(std::move(log)), units_(std::move(units)), stiffness_(stiffness), p0_(p0) {}

  void Activate() override { ++log_->activations; }
  int num_actuators() const override { return 1; }
  void Execute(std::span<const double> commands, std::span<transfer::Measurement> out) override {
    transfer::RequireOneActuator(commands, out, "recording transfer");
    const double command = commands[0];
    const long index = static_cast<long>(log_->executed.size());
    log_->executed.push_back(command);
    if (log_->throw_transfer_error_at == index) throw TransferError("recording transfer: lost");
    double force = stiffness_ * (command - p0_);
    if (log_->nan_force_at == index) force = std::numeric_limits<double>::quiet_NaN();
    out[0] = {command, force, 1.5 * static_cast<double>(index + 1)};
  }
  void Hold() noexcept override { ++log_->holds; }
  void Deactivate() override { ++log_->deactivations; }
  transfer::BenchUnits bench_units() const override { return units_; }
  std::string Describe() const override { return "recording transfer"; }

 private:
  std::shared_ptr<TransferLog> log_;
  transfer::BenchUnits units_;
  double stiffness_;  // [bench force unit / bench length unit]
  double p0_;         // [bench length unit]
};

}  // namespace hybridtest::substructures::testing
