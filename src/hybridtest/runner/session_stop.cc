// Session: how a run ends, finished or stopped, and what its observers hear (see session.h).
#include <fmt/core.h>

#include <limits>

#include "hybridtest/common/error.h"
#include "hybridtest/runner/bench_record.h"
#include "hybridtest/runner/session.h"
#include "hybridtest/runner/stop_request.h"
#include "hybridtest/transfer/safety.h"

namespace hybridtest::runner {
namespace {

// What stopped the run, by the kind of `error` (the exception being handled, `e`).
nlohmann::json StopDetails(const std::exception& e, const std::exception_ptr& error) {
  nlohmann::json stop = {{"message", e.what()}, {"kind", "error"}};
  if (!error) return stop;
  try {
    std::rethrow_exception(error);
  } catch (const transfer::SafetyStop& s) {
    const transfer::SafetyStop* safety = &s;
    stop["kind"] = "safety";
    stop["limit"] = safety->limit();
    stop["value"] = safety->value();
    stop["limit_value"] = safety->limit_value();
    stop["step"] = safety->step();
    stop["stage"] = safety->stage();
    nlohmann::json history = nlohmann::json::array();
    for (const auto& h : safety->history()) {
      history.push_back({{"step", h.step}, {"stage", h.stage}, {"command", h.command},
                         {"position", h.position}, {"force", h.force}, {"answered", h.answered}});
    }
    stop["history"] = history;
  } catch (const TransferError&) {
    stop["kind"] = "transfer";
  } catch (const Interrupted&) {
    stop["kind"] = "interrupted";
  } catch (...) {
  }
  return stop;
}

bool IsInterruption(const std::exception_ptr& error) {
  if (!error) return false;
  try {
    std::rethrow_exception(error);
  } catch (const Interrupted&) {
    return true;
  } catch (...) {
  }
  return false;
}

}  // namespace

void Session::AddCommittedState(StopEvent& event) const {
  if (!scheme_) return;
  event.committed_step = scheme_->committed().step;
  event.state = GetState();
}

StepResult Session::Finish() {
  try {
    for (auto& s : subs_) s->Deactivate();
  } catch (const std::exception& e) {
    return Fail(e);
  }
  UpdateStatistics(t_now_);
  StopEvent event;
  event.statistics = ToJson(stats_);
  event.statistics["initial_stiffness"] = stiffness_record_;
  if (!resume_) event.statistics["start"] = start_record_;  // a resume records its checks
  event.statistics["benches"] = BenchRecords(subs_, spec_);
  result_ = {SessionStatus::kFinished, ""};
  try {
    AddCommittedState(event);
    for (SessionObserver* o : observers_) o->AddStatistics(event.statistics);
    for (SessionObserver* o : observers_) o->OnStop(event);
  } catch (const std::exception& e) {
    // The run is complete, but its record could not be finished.
    error_ = std::current_exception();
    result_ = {SessionStatus::kStopped, e.what()};
  }
  return result_;
}

StepResult Session::Fail(const std::exception& e) {
  error_ = std::current_exception();
  for (auto& s : subs_) s->Hold();
  const bool interrupted = IsInterruption(error_);
  result_ = {interrupted ? SessionStatus::kHeld : SessionStatus::kStopped, e.what()};
  // A state computed but not committed (its own trial failed) is recorded without forces.
  if (scheme_ && scheme_->uncommitted() != nullptr) {
    try {
      const schemes::CommittedPoint& u = *scheme_->uncommitted();
      stats_.steps = u.step;  // the step that computed it is done; its trial failed
      t_now_ = u.t;
      Publish(RowKind::kUncommitted, u.step, u.t, u.x,
              Eigen::VectorXd::Constant(model().num_slots(),
                                        std::numeric_limits<double>::quiet_NaN()));
    } catch (const std::exception&) {
      // A record failed too; the original error is the one to report.
    }
  }
  UpdateStatistics(t_now_);
  StopEvent event;
  event.status = result_.status;
  event.reason = e.what();
  event.statistics = ToJson(stats_);
  event.statistics["initial_stiffness"] = stiffness_record_;
  if (!resume_) event.statistics["start"] = start_record_;  // a resume records its checks
  event.statistics["benches"] = BenchRecords(subs_, spec_);
  event.statistics["stop"] = StopDetails(e, error_);
  // How many commands each in-process bench had received: a resume tells it, so that a test
  // fault that stopped the run does not fire again.
  nlohmann::json received = nlohmann::json::array();
  for (const auto& s : subs_) {
    const transfer::TransferSystem* t = s->transfer_system();
    const auto count = t != nullptr ? t->commands_received() : std::nullopt;
    received.push_back(count ? nlohmann::json(*count) : nlohmann::json(nullptr));
  }
  event.statistics["stop"]["commands_received"] = received;
  try {
    AddCommittedState(event);
  } catch (const std::exception&) {
    // No state to save; the run's own error is the one reported.
  }
  for (SessionObserver* o : observers_) {
    try {
      o->AddStatistics(event.statistics);
    } catch (const std::exception&) {
      // The run's own error is the one reported.
    }
  }
  for (SessionObserver* o : observers_) {
    try {
      o->OnStop(event);
    } catch (const std::exception&) {
      // Every observer hears of the stop; the run's own error is the one reported.
    }
  }
  return result_;
}

}  // namespace hybridtest::runner
