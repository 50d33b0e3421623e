#pragma once
// QueuedObserver: hands a session's trials and commits to another observer on a thread of its
// own, through a bounded queue, so that the stepping thread does not wait on what that
// observer does (a file write and its fsync, a network send, a plot). For a real-time loop
// and for slow observers (a live monitor, a program's own recorder).
//
//   - Every event is copied into one of `capacity` preallocated slots: once started, queuing
//     allocates nothing.
//   - A full queue makes the stepping thread wait (counted in waits()); nothing is dropped and
//     the order is kept.
//   - OnStart, OnResume and OnStop are delivered on the stepping thread, after the queue has
//     been drained: the inner observer sees every event in the session's order.
//   - An exception of the inner observer is thrown on the stepping thread at the next event
//     (and stops the run like any failure).
//   - `durable_before_moves`: before every trial (a physical one moves steel) the queue is
//     drained first, so whatever the inner observer writes about a commit is done before the
//     next move (decision 0008). Without it, the inner observer may lag by up to `capacity`
//     events.
//
// The inner observer runs concurrently with the session while the queue is not empty: in
// OnTrial/OnCommit it must use the event's data only, never the Session (RunFiles, which
// asks the session for its state, is therefore not queued).
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "hybridtest/runner/session.h"

namespace hybridtest::runner {

class QueuedObserver final : public SessionObserver {
 public:
  // `inner` must outlive this observer. capacity ≥ 1.
  QueuedObserver(SessionObserver& inner, std::size_t capacity, bool durable_before_moves = false);
  ~QueuedObserver() override;
  QueuedObserver(const QueuedObserver&) = delete;
  QueuedObserver& operator=(const QueuedObserver&) = delete;

  void OnStart(const Session& session) override;
  void BeforeTrial(const schemes::TrialPoint& at) override;
  void OnTrial(const TrialEvent& event) override;
  void OnCommit(const CommitEvent& event) override;
  void OnResume(const ResumeEvent& event) override;
  void OnStop(const StopEvent& event) override;

  // Waits until the inner observer has received every queued event.
  void Drain();
  // How often the stepping thread found the queue full.
  long waits() const;

 private:
  struct Slot {
    bool commit = false;
    schemes::TrialPoint at;
    RowKind kind = RowKind::kCommitted;
    long step = 0;
    double t = 0.0;
    std::vector<double> d, r, x, row;
    std::vector<substructures::Exchange> exchanges;
  };
  Slot& Acquire(std::unique_lock<std::mutex>& lock);
  void Publish(std::unique_lock<std::mutex>& lock);
  void Work();
  void RethrowFailure();  // with mutex_ held
  void Stop();

  SessionObserver& inner_;
  std::vector<Slot> slots_;
  bool durable_;
  mutable std::mutex mutex_;
  std::condition_variable not_full_, not_empty_, drained_;
  std::size_t head_ = 0, count_ = 0;  // the oldest queued slot, and how many are queued
  bool delivering_ = false;           // the worker is inside the inner observer
  bool stop_ = false;
  long waits_ = 0;
  std::exception_ptr failure_;  // the inner observer's first exception, not yet reported
  bool failed_ = false;         // the inner observer threw once: later events are not delivered
  std::thread worker_;
};

}  // namespace hybridtest::runner
