// See lock_free_observer.h.
#include "hybridtest/runner/lock_free_observer.h"

#include <fmt/core.h>

#include <algorithm>

#include "hybridtest/common/error.h"

namespace hybridtest::runner {
namespace {

template <typename T>
void CopyInto(std::span<const T> from, std::vector<T>& to, std::size_t& n) {
  if (from.size() > to.size()) {
    throw Error("LockFreeObserver: an event longer than the sizes it was made for");
  }
  std::copy(from.begin(), from.end(), to.begin());
  n = from.size();
}

}  // namespace

LockFreeObserver::LockFreeObserver(std::vector<SessionObserver*> inner, std::size_t capacity,
                                   std::size_t row_size, std::size_t actuators,
                                   std::chrono::microseconds poll)
    : inner_(std::move(inner)),
      forward_trials_(actuators > 0),
      ring_(std::max<std::size_t>(capacity, 1),
            [row_size, actuators] {
              Slot s;
              s.x.resize(row_size);
              s.r.resize(row_size);
              s.row.resize(row_size);
              if (actuators > 0) {
                s.d.resize(row_size);
                s.exchanges.resize(actuators);
              }
              return s;
            }),
      poll_(poll) {}

LockFreeObserver::~LockFreeObserver() { Stop(); }

void LockFreeObserver::OnStart(const StartEvent& event) {
  for (SessionObserver* o : inner_) o->OnStart(event);
  running_ = true;
  consumer_ = std::thread([this] { Consume(); });
}

void LockFreeObserver::RethrowFailure() {
  const std::lock_guard<std::mutex> lock(error_mutex_);  // uncontended: the consumer takes it
  if (error_) std::rethrow_exception(error_);            // only to store a failure
}

LockFreeObserver::Slot* LockFreeObserver::ClaimOrThrow() {
  RethrowFailure();
  Slot* s = ring_.Claim();
  if (s == nullptr) {
    throw Error(fmt::format("the observers' queue is full ({} events): the files cannot keep "
                            "up with the real-time loop; the test is stopped safely. Raise "
                            "real_time.queue or write to a faster disk", ring_.capacity()));
  }
  return s;
}

void LockFreeObserver::OnTrial(const TrialEvent& e) {
  if (!forward_trials_) return;
  Slot* s = ClaimOrThrow();
  s->trial = true;
  s->at = e.at;
  CopyInto(e.d, s->d, s->nd);
  CopyInto(e.r, s->r, s->nr);
  CopyInto(e.exchanges, s->exchanges, s->nexchanges);
  ring_.Publish();
}

void LockFreeObserver::OnCommit(const CommitEvent& e) {
  Slot* s = ClaimOrThrow();
  s->trial = false;
  s->kind = e.kind;
  s->step = e.step;
  s->t = e.t;
  CopyInto(e.x, s->x, s->nx);
  CopyInto(e.r, s->r, s->nr);
  CopyInto(e.row, s->row, s->nrow);
  s->statistics = e.statistics;
  s->finished = e.finished;
  s->steps_left = e.steps_left;
  ring_.Publish();
}

void LockFreeObserver::Deliver(const Slot& s) {
  if (s.trial) {
    const TrialEvent e{s.at, {s.d.data(), s.nd}, {s.r.data(), s.nr},
                       {s.exchanges.data(), s.nexchanges}};
    for (SessionObserver* o : inner_) o->OnTrial(e);
    return;
  }
  // A queued commit: no state to call back for, no pacer sample (session.h).
  CommitEvent e;
  e.kind = s.kind;
  e.step = s.step;
  e.t = s.t;
  e.x = {s.x.data(), s.nx};
  e.r = {s.r.data(), s.nr};
  e.row = {s.row.data(), s.nrow};
  e.statistics = s.statistics;
  e.finished = s.finished;
  e.steps_left = s.steps_left;
  for (SessionObserver* o : inner_) o->OnCommit(e);
}

void LockFreeObserver::Consume() {
  while (true) {
    Slot* s = ring_.Front();
    if (s == nullptr) {
      if (!running_.load()) return;
      std::this_thread::sleep_for(poll_);
      continue;
    }
    try {
      Deliver(*s);
    } catch (...) {
      const std::lock_guard<std::mutex> lock(error_mutex_);
      if (!error_) error_ = std::current_exception();
    }
    ring_.Pop();
  }
}

void LockFreeObserver::Drain() {
  while (!ring_.empty() && consumer_.joinable()) std::this_thread::sleep_for(poll_);
}

void LockFreeObserver::WaitForFree(std::size_t n) {
  n = std::min(n, ring_.capacity());
  while (ring_.free_slots() < n && consumer_.joinable()) std::this_thread::sleep_for(poll_);
}

void LockFreeObserver::Stop() {
  if (!consumer_.joinable()) return;
  Drain();
  running_ = false;
  consumer_.join();
}

void LockFreeObserver::OnResume(const ResumeEvent& event) {
  Drain();
  RethrowFailure();
  for (SessionObserver* o : inner_) o->OnResume(event);
}

void LockFreeObserver::OnOperatorAction(const nlohmann::json& action) {
  Drain();
  RethrowFailure();
  for (SessionObserver* o : inner_) o->OnOperatorAction(action);
}

void LockFreeObserver::AddStatistics(nlohmann::json& statistics) {
  Drain();
  for (SessionObserver* o : inner_) o->AddStatistics(statistics);
}

void LockFreeObserver::OnStop(const StopEvent& event) {
  Stop();
  // Every observer hears of the stop; the first failure is reported after.
  std::exception_ptr failure;
  for (SessionObserver* o : inner_) {
    try {
      o->OnStop(event);
    } catch (...) {
      if (!failure) failure = std::current_exception();
    }
  }
  if (!failure) {
    const std::lock_guard<std::mutex> lock(error_mutex_);
    failure = error_;  // a failure of the last events, which no later event reported
  }
  if (failure) std::rethrow_exception(failure);
}

}  // namespace hybridtest::runner
