#pragma once
// BoundedCall: runs a Python callback on a thread of its own so that its caller waits at most a
// deadline. A Python thread cannot be killed: a call that does not return in time is left
// running (abandoned), and its result, whenever it comes, is dropped. The caller meanwhile gets
// `false` back at the deadline and stops the run; the next Run() on a BoundedCall whose call is
// still running is refused the same way, at once.
//
// The caller waits without the GIL (released here if it holds it), so the job can take it, and
// so that the caller, on the main thread, can check for Ctrl-C every few milliseconds
// (PyErr_CheckSignals): a SIGINT turns into `interrupted` even while the job is stuck in C.
//
// One job at a time; one worker thread per BoundedCall, started on the first Run(). The
// destructor joins an idle worker and detaches a busy one (it ends when its call returns).
#include <pybind11/pybind11.h>

#include <functional>
#include <memory>
#include <optional>

namespace hybridtest::python {

class BoundedCall {
 public:
  enum class Outcome { kDone, kTimedOut, kBusy, kInterrupted };

  BoundedCall() = default;
  ~BoundedCall();
  BoundedCall(const BoundedCall&) = delete;
  BoundedCall& operator=(const BoundedCall&) = delete;

  // Runs `job` on the worker and waits for it at most `timeout` [s]. kDone: the job returned
  // (an exception it threw is rethrown here). kTimedOut: it is still running. kBusy: an earlier
  // job is still running, `job` was not started. kInterrupted: Ctrl-C while waiting; *signal
  // holds the KeyboardInterrupt (fetched with the GIL), and the job still runs. `job` must keep
  // alive what it uses (it may outlive this call and this object) and takes the GIL itself.
  Outcome Run(std::function<void()> job, double timeout,
              std::optional<pybind11::error_already_set>* signal);

 private:
  struct State;
  std::shared_ptr<State> state_;
};

}  // namespace hybridtest::python
