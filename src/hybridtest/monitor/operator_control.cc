// See operator_control.h.
#include "hybridtest/monitor/operator_control.h"

#include <chrono>

#include "hybridtest/io/utc_time.h"

namespace hybridtest::monitor {

const char* ActionName(OperatorAction action) {
  switch (action) {
    case OperatorAction::kHold: return "hold";
    case OperatorAction::kContinue: return "continue";
    case OperatorAction::kStop: return "stop";
  }
  return "?";
}

bool OperatorControl::holding() const {
  std::lock_guard lock(mutex_);
  return holding_;
}

ActionReply OperatorControl::Request(OperatorAction action, const std::string& origin) {
  const std::string status = state_.status();
  std::lock_guard lock(mutex_);
  if (status == "finished" || status == "stopped" || stop_asked_) {
    return {409, "the run is not running (" + status + "): nothing to " + ActionName(action)};
  }
  if (action == OperatorAction::kHold && holding_) return {409, "the run holds already"};
  if (action == OperatorAction::kContinue && !holding_) {
    return {409, "the run is not holding: Continue follows a Hold"};
  }
  if (action == OperatorAction::kHold) holding_ = true;
  if (action == OperatorAction::kContinue) holding_ = false;
  if (action == OperatorAction::kStop) stop_asked_ = true;
  queue_.push_back({action, origin, io::UtcNowIso8601()});
  pending_.store(true, std::memory_order_release);
  changed_.notify_all();
  return {200, std::string(ActionName(action)) + " accepted"};
}

void OperatorControl::Apply(runner::Session& session, std::unique_lock<std::mutex>& lock) {
  std::vector<Pending> queue;
  queue.swap(queue_);
  pending_.store(false, std::memory_order_relaxed);
  lock.unlock();
  const auto& p = session.committed();
  for (const Pending& a : queue) {
    nlohmann::json record = {{"action", ActionName(a.action)}, {"origin", a.origin},
                             {"asked_at", a.asked_at}, {"applied_at", io::UtcNowIso8601()},
                             {"step", p.step}, {"t", p.t}};
    try {
      session.RecordOperatorAction(record);
    } catch (const std::exception& e) {
      record["record_error"] = e.what();  // the action still applies; the page says so
    }
    state_.AddAction(record);
  }
  lock.lock();
}

runner::StepResult OperatorControl::BetweenSteps(runner::Session& session) {
  if (!pending_.load(std::memory_order_acquire)) return session.result();
  std::unique_lock lock(mutex_);
  Apply(session, lock);
  if (stop_asked_) {
    lock.unlock();
    return session.InterruptBetweenSteps();  // no step in progress: nothing more moves
  }
  if (!holding_) return session.result();
  // Hold: every substructure holds; wait for Continue or Stop (or the session's own stop
  // request, e.g. Ctrl-C).
  session.HoldBetweenSteps();
  state_.SetStatus("holding");
  while (holding_ && !stop_asked_ && !session.stop_requested()) {
    changed_.wait_for(lock, std::chrono::milliseconds(100));
    if (pending_.load(std::memory_order_relaxed)) Apply(session, lock);
  }
  if (pending_.load(std::memory_order_relaxed)) Apply(session, lock);
  const bool stop = stop_asked_ || session.stop_requested();
  lock.unlock();
  if (stop) return session.InterruptBetweenSteps();
  const runner::StepResult result = session.ContinueAfterHold();
  if (result.status == runner::SessionStatus::kWorking) state_.SetStatus("running");
  return result;
}

}  // namespace hybridtest::monitor
