#pragma once
// LockFreeObserver: hands a session's trials and committed rows to other observers (the run's
// files, the progress display, a program's own recorder) on a thread of their own through an
// SpscRing (spsc_ring.h), for a paced (real-time) loop: the stepping thread copies the event
// into a preallocated slot and returns, never waiting, never allocating and never writing a
// file.
//
//   - A FULL ring stops the test safely: OnCommit/OnTrial throw hybridtest::Error naming the
//     capacity, which the Session turns into a stop with every actuator holding. A paced loop
//     does not let it come to that: it holds the run while free_slots() is still above
//     kQueueReserve (paced_loop.h), so that every committed row is kept.
//   - The consumer thread polls the ring (sleeping `poll` between empty looks) and delivers
//     every event to every inner observer, in the session's order.
//   - OnStart, OnResume, OnOperatorAction, AddStatistics and OnStop are delivered on the stepping thread after
//     the ring is drained (the consumer is then idle), so the inner observers see every event
//     in order; an inner observer's exception is rethrown on the stepping thread at the next
//     event. BeforeTrial is not forwarded.
//   - The inner observers run concurrently with the session while the ring is not empty: in
//     OnTrial/OnCommit they must use the event's data only, never the Session (RunFiles, in a
//     real-time run, saves its state at the stop: run_files.h). A queued commit carries
//     everything of the session's event but its `state` (empty).
#include <atomic>
#include <chrono>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "hybridtest/runner/session.h"
#include "hybridtest/runner/spsc_ring.h"

namespace hybridtest::runner {

// The free slots below which a paced loop holds the run: room for the step in progress (its
// trial, its row) and the stop's own rows.
inline constexpr std::size_t kQueueReserve = 16;

class LockFreeObserver final : public SessionObserver {
 public:
  // `inner` must outlive this observer. `row_size`: the journal row's length (the session's
  // JournalChannels), which bounds x, r and d too; `actuators`: exchanges per trial (0: trials
  // are not forwarded). capacity ≥ 1 events.
  LockFreeObserver(std::vector<SessionObserver*> inner, std::size_t capacity,
                   std::size_t row_size, std::size_t actuators = 0,
                   std::chrono::microseconds poll = std::chrono::microseconds(200));
  LockFreeObserver(SessionObserver& inner, std::size_t capacity, std::size_t row_size)
      : LockFreeObserver(std::vector<SessionObserver*>{&inner}, capacity, row_size) {}
  ~LockFreeObserver() override;
  LockFreeObserver(const LockFreeObserver&) = delete;
  LockFreeObserver& operator=(const LockFreeObserver&) = delete;

  void OnStart(const StartEvent& event) override;
  void OnTrial(const TrialEvent& event) override;
  void OnCommit(const CommitEvent& event) override;
  void OnResume(const ResumeEvent& event) override;
  // Delivered like OnResume: after the ring is drained, on the stepping thread (operator
  // actions are rare and come between steps).
  void OnOperatorAction(const nlohmann::json& action) override;
  void AddStatistics(nlohmann::json& statistics) override;
  void OnStop(const StopEvent& event) override;
  bool real_time_safe() const override { return true; }

  // Waits until the consumer has delivered every published event.
  void Drain();
  // Waits until at least `n` events fit (a virtual-time loop, which has no deadline).
  void WaitForFree(std::size_t n);
  // Producer side: events that can still be queued.
  std::size_t free_slots() const { return ring_.free_slots(); }
  std::size_t capacity() const { return ring_.capacity(); }

 private:
  struct Slot {
    bool trial = false;
    // A commit.
    RowKind kind = RowKind::kCommitted;
    long step = 0;
    double t = 0.0;
    std::vector<double> x, r, row;
    std::size_t nx = 0, nr = 0, nrow = 0;
    RunStatistics statistics;
    bool finished = false;
    long steps_left = 0;
    // A trial (r above).
    schemes::TrialPoint at;
    std::vector<double> d;
    std::size_t nd = 0;
    std::vector<substructures::Exchange> exchanges;
    std::size_t nexchanges = 0;
  };
  Slot* ClaimOrThrow();
  void RethrowFailure();
  void Consume();
  void Deliver(const Slot& s);
  void Stop();

  std::vector<SessionObserver*> inner_;
  bool forward_trials_;
  SpscRing<Slot> ring_;
  std::chrono::microseconds poll_;
  std::atomic<bool> running_{false};
  std::thread consumer_;
  std::mutex error_mutex_;
  std::exception_ptr error_;
};

}  // namespace hybridtest::runner
