#pragma once
// OperatorControl: the operator's Hold, Continue and Stop, as on a test controller, between the
// monitor's HTTP threads (which ask) and the run's stepping thread (which acts, between two
// steps). Never a command that moves an actuator anywhere else.
//
//   Hold      the run pauses after the step in progress; every substructure holds its
//             position (Session::HoldBetweenSteps) until Continue or Stop.
//   Continue  from a hold: the substructures are activated again and stepping goes on, from
//             the same committed state (on an ideal bench the journal is the one of a run
//             that never held, in t, q, u and r).
//   Stop      as Ctrl-C: the run ends between two steps, without another one
//             (Session::InterruptBetweenSteps), every committed row on disk, resumable; the
//             command exits with 130.
//
// Every accepted action is written to the sidecar's "operator_actions" (Session::
// RecordOperatorAction) by the stepping thread when it applies it: the action, the UTC time
// it was asked and applied, its origin (address and client), and the step and t it applied
// at. The stepping thread's cost when nothing is asked is one atomic load per step.
#include <atomic>
#include <condition_variable>
#include <mutex>
#include <string>
#include <vector>

#include "hybridtest/monitor/monitor_state.h"
#include "hybridtest/runner/session.h"

namespace hybridtest::monitor {

enum class OperatorAction { kHold, kContinue, kStop };
const char* ActionName(OperatorAction action);

struct ActionReply {
  int http_status = 200;  // 200 accepted; 409 not possible in the run's state
  std::string message;
};

class OperatorControl {
 public:
  explicit OperatorControl(MonitorState& state) : state_(state) {}

  // Any thread (the HTTP server's): asks for an action from `origin` ("127.0.0.1 (curl/8)").
  ActionReply Request(OperatorAction action, const std::string& origin);

  // The stepping thread, before every Step(): applies what was asked. Blocks while the run
  // holds (until Continue, Stop or the session's own stop request, e.g. Ctrl-C). Returns the
  // session's result (kStopped if a bench refused to continue).
  runner::StepResult BetweenSteps(runner::Session& session);

  bool holding() const;

 private:
  struct Pending {
    OperatorAction action;
    std::string origin;
    std::string asked_at;  // UTC
  };
  void Apply(runner::Session& session, std::unique_lock<std::mutex>& lock);

  MonitorState& state_;
  std::atomic<bool> pending_{false};
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<Pending> queue_;
  bool holding_ = false;       // the stepping thread holds (or will at the next step)
  bool stop_asked_ = false;
};

}  // namespace hybridtest::monitor
