#pragma once
// MonitorObserver: the live monitor as a session observer. It never blocks the stepping
// thread and never allocates there: every committed row is copied as one small frame (step,
// t, wall and lab time, evaluations, d and r per slot, command/position/force per physical
// actuator; monitor_state.h) into a preallocated FrameRing, or dropped (and counted) if the
// ring is full. A collector thread of its own drains the ring into the MonitorState every
// `drain_interval`; the HTTP server reads only the MonitorState. A slow, stalled or absent
// viewer therefore costs the run nothing but the copy.
//
// d is the slot displacement of the last stage-0 trial (the trial at the committed state);
// what the seam reports, per slot and per physical actuator, is all it reads (TrialEvent,
// CommitEvent's journal row); the limits and identity come from the run's spec.
#include <condition_variable>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "hybridtest/monitor/frame_ring.h"
#include "hybridtest/monitor/monitor_state.h"
#include "hybridtest/runner/session.h"

namespace hybridtest::monitor {

struct MonitorObserverOptions {
  std::size_t ring_capacity = 4096;  // frames queued between two drains
  double drain_interval = 0.05;      // collector period. Unit: [s]
};

// The identity, layout and actuators of a session's run, from its spec.
void DescribeRun(const runner::Session& session, RunIdentity& identity, FrameLayout& layout,
                 std::vector<ActuatorInfo>& actuators);

class MonitorObserver final : public runner::SessionObserver {
 public:
  // `state` must outlive the observer.
  explicit MonitorObserver(MonitorState& state, MonitorObserverOptions options = {});
  ~MonitorObserver() override;
  MonitorObserver(const MonitorObserver&) = delete;
  MonitorObserver& operator=(const MonitorObserver&) = delete;

  void OnStart(const runner::Session& session) override;
  void OnTrial(const runner::TrialEvent& event) override;
  void OnCommit(const runner::CommitEvent& event) override;
  void OnResume(const runner::ResumeEvent& event) override;
  void OnStop(const runner::StopEvent& event) override;
  // Copies into its ring or drops: a paced run keeps it on the stepping thread.
  bool real_time_safe() const override { return true; }

  long dropped() const { return ring_ ? ring_->dropped() : 0; }

 private:
  void Collect();       // the collector thread
  void DrainNow();      // ring → state (collector, or the stepping thread at the stop)
  void StopCollector();

  MonitorState& state_;
  MonitorObserverOptions options_;
  const runner::Session* session_ = nullptr;
  FrameLayout layout_;
  std::unique_ptr<FrameRing> ring_;
  std::vector<double> last_d_;  // (m) d of the last stage-0 trial
  std::mutex mutex_;            // the collector's wake-up and the drain
  std::condition_variable wake_;
  bool stop_ = false;
  std::thread collector_;
};

}  // namespace hybridtest::monitor
