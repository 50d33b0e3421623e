#pragma once
// Test double for the runner: a substructure that answers like a spring and records every
// call (trial, commit, hold, activate, deactivate) into a log shared by all substructures of
// a run, so that the order of calls across substructures can be checked. It can fail at a
// given (step, stage) with a TransferError or a SafetyStop.
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/substructures/substructure.h"
#include "hybridtest/transfer/safety.h"

namespace hybridtest::runner::testing {

enum class CallKind { kActivate, kTrial, kCommit, kHold, kDeactivate };

struct Call {
  CallKind kind;
  int slot = 0;
  long step = 0;   // trials only
  int stage = 0;   // trials only
  double t = 0.0;  // trials only [s]
  double d = 0.0;  // trials only [m]
  double r = 0.0;  // trials only: what was returned [N] (NaN if it threw)
};

struct Failure {
  long step = 0;
  int stage = 0;
  bool safety = false;  // SafetyStop, else TransferError
};

class FakeSubstructure final : public substructures::Substructure {
 public:
  // r = stiffness · d + kStageTag · stage: the tag makes a stage-1 force distinguishable from
  // the stage-0 force of the same step.
  static constexpr double kStageTag = 0.25;  // [N]
  static constexpr double kP0 = 0.02;        // [m], for the physical channels

  FakeSubstructure(int slot, std::shared_ptr<std::vector<Call>> log, double stiffness,
                   bool physical, std::optional<Failure> failure = std::nullopt)
      : slot_(slot), log_(std::move(log)), stiffness_(stiffness), physical_(physical),
        failure_(failure) {}

  void Activate() override { log_->push_back({CallKind::kActivate, slot_}); }
  void Trial(std::span<const double> ds, std::span<double> rs,
             const substructures::TrialContext& c) override {
    const double d = ds[0];
    if (failure_ && failure_->step == c.step && failure_->stage == c.stage) {
      log_->push_back({CallKind::kTrial, slot_, c.step, c.stage, c.t, d,
                       std::numeric_limits<double>::quiet_NaN()});
      if (failure_->safety) {
        throw transfer::SafetyStop("stroke_max", kP0 + d, 0.0, c.step, c.stage,
                                   {{c.step, c.stage, kP0 + d, 0.0, 0.0, false}},
                                   "fake stroke limit");
      }
      throw TransferError("fake: connection lost");
    }
    const double r = stiffness_ * d + kStageTag * c.stage;
    log_->push_back({CallKind::kTrial, slot_, c.step, c.stage, c.t, d, r});
    ++evaluations_;
    last_ = {kP0 + d, kP0 + d, r, 0.5 * static_cast<double>(evaluations_)};
    rs[0] = r;
  }
  void Commit() override { log_->push_back({CallKind::kCommit, slot_}); }
  void Hold() noexcept override { log_->push_back({CallKind::kHold, slot_}); }
  void Deactivate() override { log_->push_back({CallKind::kDeactivate, slot_}); }
  bool is_physical() const override { return physical_; }
  substructures::Exchange actuator_exchange(int /*k*/) const override { return last_; }
  long evaluations() const override { return physical_ ? evaluations_ : 0; }
  std::string Describe() const override { return "fake spring"; }

 private:
  int slot_;
  std::shared_ptr<std::vector<Call>> log_;
  double stiffness_;
  bool physical_;
  std::optional<Failure> failure_;
  long evaluations_ = 0;
  substructures::Exchange last_;
};

}  // namespace hybridtest::runner::testing
