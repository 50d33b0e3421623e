#pragma once
// MonitorObserver: the live monitor as a session observer. It never blocks the stepping
// thread and never allocates there: every committed row is copied as one small frame (step,
// t, wall and lab time, evaluations, d and r per slot, command/position/force per physical
// actuator; monitor_state.h) into a preallocated runner::SpscRing, or dropped (and counted) if the
// ring is full. A collector thread of its own drains the ring into the MonitorState every
// `drain_interval`; the HTTP server reads only the MonitorState. A slow, stalled or absent
// viewer therefore costs the run nothing but the copy.
//
// d is the slot displacement of the last stage-0 trial (the trial at the committed state);
// what the seam reports, per model slot and per actuator, is all it reads (TrialEvent,
// CommitEvent's journal row). The actuators, their names, p0 and limits come from the
// session's slot map and each substructure's actuator_p0/actuator_limits (decision 0016);
// the identity from the run's spec (StartEvent). On a paced run each committed row carries the
// pacer's sample (CommitEvent::real_time: counts, lateness, J1–J3 and the compensator's delay
// estimate per actuator), which it copies into the frame on the stepping thread, allocating
// nothing; it holds no pointer to the Session, the pacer or a transfer system.
#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "hybridtest/monitor/monitor_state.h"
#include "hybridtest/runner/session.h"
#include "hybridtest/runner/spsc_ring.h"

namespace hybridtest::monitor {

struct MonitorObserverOptions {
  std::size_t ring_capacity = 4096;  // frames queued between two drains
  double drain_interval = 0.05;      // collector period. Unit: [s]
};

// The identity, layout and actuators of a run, from its spec and slot map.
void DescribeRun(const runner::StartEvent& run, RunIdentity& identity, FrameLayout& layout,
                 std::vector<ActuatorInfo>& actuators);

class MonitorObserver final : public runner::SessionObserver {
 public:
  // `state` must outlive the observer.
  explicit MonitorObserver(MonitorState& state, MonitorObserverOptions options = {});
  ~MonitorObserver() override;
  MonitorObserver(const MonitorObserver&) = delete;
  MonitorObserver& operator=(const MonitorObserver&) = delete;

  void OnStart(const runner::StartEvent& run) override;
  void OnTrial(const runner::TrialEvent& event) override;
  void OnCommit(const runner::CommitEvent& event) override;
  void OnResume(const runner::ResumeEvent& event) override;
  void OnStop(const runner::StopEvent& event) override;
  // Copies into its ring or drops: a paced run keeps it on the stepping thread.
  bool real_time_safe() const override { return true; }

  long dropped() const { return dropped_.load(std::memory_order_relaxed); }

 private:
  void Collect();       // the collector thread
  void DrainNow();      // ring → state (collector, or the stepping thread at the stop)
  void StopCollector();
  // The paced loop's per-tick columns, from the sample a committed row carries.
  void FillRealTime(const runner::RealTimeSample* sample, double* frame) const;

  MonitorState& state_;
  MonitorObserverOptions options_;
  std::string csv_;  // the run's journal ("" without files), for the resume command
  // The actuators (run's order) behind a compensator, in the order of their delay columns;
  // their delays come with the pacer's sample (RealTimeSample::compensated_delay_s).
  std::vector<std::size_t> compensated_;
  FrameLayout layout_;
  std::unique_ptr<runner::SpscRing<std::vector<double>>> ring_;  // frames (layout_.width())
  std::atomic<long> dropped_{0};  // frames a full ring dropped (the stepping thread counts)
  std::vector<double> last_d_;  // (m) d of the last stage-0 trial
  std::mutex mutex_;            // the collector's wake-up and the drain
  std::condition_variable wake_;
  bool stop_ = false;
  std::thread collector_;
};

}  // namespace hybridtest::monitor
