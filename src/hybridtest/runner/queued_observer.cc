// See queued_observer.h.
#include "hybridtest/runner/queued_observer.h"

#include "hybridtest/common/error.h"
#include "hybridtest/runner/run_record.h"

namespace hybridtest::runner {
namespace {

template <class T>
void CopyInto(std::vector<T>& to, std::span<const T> from) {
  to.assign(from.begin(), from.end());  // the slot was sized at the start: no allocation
}

}  // namespace

QueuedObserver::QueuedObserver(SessionObserver& inner, std::size_t capacity,
                               bool durable_before_moves)
    : inner_(inner), slots_(capacity), durable_(durable_before_moves) {
  if (capacity == 0) throw ConfigError("QueuedObserver: capacity 0; give at least one slot");
}

QueuedObserver::~QueuedObserver() { Stop(); }

void QueuedObserver::OnStart(const Session& session) {
  const std::size_t m = static_cast<std::size_t>(session.model().num_slots());
  std::size_t physical = 0;
  for (const auto& s : session.substructures()) physical += s->is_physical() ? 1 : 0;
  const std::size_t row = JournalChannels(session.spec()).size();
  for (Slot& s : slots_) {
    s.d.reserve(m);
    s.r.reserve(m);
    s.x.reserve(row - 1 - m - 4 * physical);
    s.row.reserve(row);
    s.exchanges.reserve(physical);
  }
  inner_.OnStart(session);
  if (!worker_.joinable()) worker_ = std::thread([this] { Work(); });
}

void QueuedObserver::RethrowFailure() {
  if (failure_) {
    std::exception_ptr failure = failure_;
    failure_ = nullptr;
    std::rethrow_exception(failure);
  }
}

QueuedObserver::Slot& QueuedObserver::Acquire(std::unique_lock<std::mutex>& lock) {
  RethrowFailure();
  if (count_ == slots_.size()) {
    ++waits_;
    not_full_.wait(lock, [this] { return count_ < slots_.size(); });
  }
  return slots_[(head_ + count_) % slots_.size()];
}

void QueuedObserver::Publish(std::unique_lock<std::mutex>& lock) {
  ++count_;
  lock.unlock();
  not_empty_.notify_one();
}

void QueuedObserver::BeforeTrial(const schemes::TrialPoint&) {
  if (durable_) Drain();
}

void QueuedObserver::OnTrial(const TrialEvent& e) {
  std::unique_lock<std::mutex> lock(mutex_);
  Slot& s = Acquire(lock);
  s.commit = false;
  s.at = e.at;
  CopyInto(s.d, e.d);
  CopyInto(s.r, e.r);
  CopyInto(s.exchanges, e.exchanges);
  Publish(lock);
}

void QueuedObserver::OnCommit(const CommitEvent& e) {
  std::unique_lock<std::mutex> lock(mutex_);
  Slot& s = Acquire(lock);
  s.commit = true;
  s.kind = e.kind;
  s.step = e.step;
  s.t = e.t;
  CopyInto(s.x, e.x);
  CopyInto(s.r, e.r);
  CopyInto(s.row, e.row);
  Publish(lock);
}

void QueuedObserver::OnResume(const ResumeEvent& e) {
  Drain();
  inner_.OnResume(e);
}

void QueuedObserver::OnStop(const StopEvent& e) {
  // The inner observer hears of the stop even when it failed: its failure, if not yet reported,
  // is raised after it.
  std::exception_ptr pending;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    drained_.wait(lock, [this] { return count_ == 0 && !delivering_; });
    pending = failure_;
    failure_ = nullptr;
  }
  inner_.OnStop(e);
  if (pending) std::rethrow_exception(pending);
}

void QueuedObserver::Drain() {
  std::unique_lock<std::mutex> lock(mutex_);
  drained_.wait(lock, [this] { return count_ == 0 && !delivering_; });
  RethrowFailure();
}

long QueuedObserver::waits() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return waits_;
}

void QueuedObserver::Work() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    not_empty_.wait(lock, [this] { return count_ > 0 || stop_; });
    if (count_ == 0) return;  // stopped and drained
    Slot& s = slots_[head_];
    delivering_ = true;
    lock.unlock();
    // The slot stays reserved (count_ includes it) until delivered.
    std::exception_ptr failure;
    try {
      if (failed_) {
        // A broken inner observer gets nothing after its first failure (the run is stopping).
      } else if (s.commit) {
        inner_.OnCommit({s.kind, s.step, s.t, s.x, s.r, s.row});
      } else {
        inner_.OnTrial({s.at, s.d, s.r, s.exchanges});
      }
    } catch (...) {
      failure = std::current_exception();  // reported on the stepping thread
    }
    lock.lock();
    if (failure && !failed_) {
      failure_ = failure;
      failed_ = true;
    }
    delivering_ = false;
    head_ = (head_ + 1) % slots_.size();
    --count_;
    not_full_.notify_one();
    if (count_ == 0) drained_.notify_all();
  }
}

void QueuedObserver::Stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  not_empty_.notify_one();
  if (worker_.joinable()) worker_.join();
}

}  // namespace hybridtest::runner
