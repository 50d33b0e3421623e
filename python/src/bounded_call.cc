// See bounded_call.h.
#include "bounded_call.h"

#include <cxxabi.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>
#include <utility>

namespace hybridtest::python {

// Shared by the caller and the worker thread; the worker keeps it alive after a detach.
struct BoundedCall::State {
  std::mutex mutex;
  std::condition_variable wake;   // a job, or quit, for the worker
  std::condition_variable done;   // the job returned, for the caller
  std::function<void()> job;      // the pending job (empty: none)
  bool running = false;           // a job is pending or running
  bool quit = false;
  std::exception_ptr error;       // what the last job threw
  std::thread worker;

  void Loop() {
    std::unique_lock lock(mutex);
    for (;;) {
      wake.wait(lock, [this] { return quit || job; });
      if (!job) return;  // quit, idle
      std::function<void()> run = std::move(job);
      job = nullptr;
      lock.unlock();
      std::exception_ptr thrown;
      try {
        run();
      } catch (abi::__forced_unwind&) {
        throw;  // the interpreter ends this thread (finalization): let it
      } catch (...) {
        thrown = std::current_exception();
      }
      run = nullptr;  // drops what the job held (it takes the GIL itself if it must)
      lock.lock();
      error = thrown;
      running = false;
      done.notify_all();
      if (quit) return;
    }
  }
};

BoundedCall::~BoundedCall() {
  if (!state_) return;
  std::unique_lock lock(state_->mutex);
  state_->quit = true;
  const bool busy = state_->running;
  state_->wake.notify_all();
  lock.unlock();
  // A busy worker is in Python and may wait for the GIL, which the caller may hold: detached,
  // it ends when its call returns.
  if (busy) {
    state_->worker.detach();
  } else {
    state_->worker.join();
  }
}

BoundedCall::Outcome BoundedCall::Run(std::function<void()> job, double timeout,
                                      std::optional<pybind11::error_already_set>* signal) {
  if (!state_) {
    state_ = std::make_shared<State>();
    state_->worker = std::thread([s = state_] { s->Loop(); });
  }
  State& s = *state_;
  {
    std::lock_guard lock(s.mutex);
    if (s.running) return Outcome::kBusy;
    s.job = std::move(job);
    s.running = true;
    s.error = nullptr;
    s.wake.notify_all();
  }
  // Wait without the GIL, in slices, checking for Ctrl-C (main thread only) between them.
  // (a timeout beyond a year is no deadline: the duration would overflow the clock)
  const auto deadline =
      std::chrono::steady_clock::now() +
      std::chrono::duration_cast<std::chrono::steady_clock::duration>(
          std::chrono::duration<double>(std::clamp(timeout, 0.0, 3.2e7)));
  const bool had_gil = PyGILState_Check() != 0;
  std::unique_lock lock(s.mutex);
  for (;;) {
    const auto slice = std::min(deadline, std::chrono::steady_clock::now() +
                                              std::chrono::milliseconds(20));
    {
      std::optional<pybind11::gil_scoped_release> release;
      if (had_gil) release.emplace();
      s.done.wait_until(lock, slice, [&s] { return !s.running; });
    }
    if (!s.running) break;
    if (std::chrono::steady_clock::now() >= deadline) return Outcome::kTimedOut;
    lock.unlock();
    {
      pybind11::gil_scoped_acquire gil;
      if (signal != nullptr && PyErr_CheckSignals() != 0) {
        signal->emplace();  // fetches the KeyboardInterrupt
        return Outcome::kInterrupted;
      }
    }
    lock.lock();
  }
  if (s.error) std::rethrow_exception(std::exchange(s.error, nullptr));
  return Outcome::kDone;
}

}  // namespace hybridtest::python
