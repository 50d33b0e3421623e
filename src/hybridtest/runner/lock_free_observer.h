#pragma once
// LockFreeObserver: hands a session's committed rows to another observer on a thread of its
// own through an SpscRing (spsc_ring.h), for a paced (real-time) loop: the stepping thread
// copies the row into a preallocated slot and returns, never waiting and never allocating. A
// FULL ring stops the test safely: OnCommit throws hybridtest::Error naming the capacity, which
// the Session turns into a stop with every actuator holding (real_time.queue sets the capacity).
// The consumer thread polls the ring (sleeping `poll` between empty looks). OnStart and OnStop
// are delivered on the stepping thread after the ring is drained, so the inner observer sees
// every row in order; an exception of the inner observer is rethrown at the next OnCommit.
// Trials are not forwarded. The inner observer must use the event's data only, never the
// Session (RunFiles, which reads the session's state, is not queued).
#include <atomic>
#include <chrono>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "hybridtest/runner/session.h"
#include "hybridtest/runner/spsc_ring.h"

namespace hybridtest::runner {

class LockFreeObserver final : public SessionObserver {
 public:
  // `inner` must outlive this observer; `row_size`: the journal row's length (the session's
  // JournalChannels). capacity ≥ 1.
  LockFreeObserver(SessionObserver& inner, std::size_t capacity, std::size_t row_size,
                   std::chrono::microseconds poll = std::chrono::microseconds(200));
  ~LockFreeObserver() override;
  LockFreeObserver(const LockFreeObserver&) = delete;
  LockFreeObserver& operator=(const LockFreeObserver&) = delete;

  void OnStart(const Session& session) override;
  void OnCommit(const CommitEvent& event) override;
  void OnStop(const StopEvent& event) override;

  // Waits until the consumer has delivered every published row.
  void Drain();
  long delivered() const { return delivered_.load(); }

 private:
  struct Slot {
    RowKind kind = RowKind::kCommitted;
    long step = 0;
    double t = 0.0;
    std::vector<double> x, r, row;
    std::size_t nx = 0, nr = 0, nrow = 0;
  };
  void Consume();
  void Stop();

  SessionObserver& inner_;
  SpscRing<Slot> ring_;
  std::chrono::microseconds poll_;
  std::atomic<bool> running_{false};
  std::atomic<long> delivered_{0};
  std::thread consumer_;
  std::mutex error_mutex_;
  std::exception_ptr error_;
};

}  // namespace hybridtest::runner
