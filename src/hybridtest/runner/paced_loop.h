#pragma once
// PacedLoop: the real-time setting of a Session (decisions 0015, 0016): its StepPacer, built by
// the Session from its spec's `real_time:` block. The Session owns the clock, the pacer, the
// one loop (Session::Run) and the step. The
// constructor refuses, before anything moves, a scheme that cannot run paced and any physical
// substructure whose transfer system cannot (TransferSystem::can_run_paced: a lab-time bench);
// after Initialize() (the settled trial at x_0) every physical substructure's transfer system,
// whatever its number of actuators, is started paced (TransferSystem::StartPaced, found
// through the session's slot map), then tick k = 1, 2, … waits for its ABSOLUTE deadline
// t_0 + k·h (h the scheme's fixed step; never accumulated, so nothing drifts) and the session
// steps once: one command per actuator per tick, the measurement of that tick read without
// settling. The wall clock's wait sleeps until shortly before the deadline and spins the
// rest (MonotonicClock::WaitUntil: a sleep wakes late by the timer slack; the spin does not).
//
// An operator's hold between two ticks (the live monitor, through Session::SetBetweenSteps)
// holds every actuator at once; after Continue the ticks start again one step after it (the
// held time is neither a miss nor made up).
//
// Per tick it records, in preallocated storage (the loop allocates nothing):
//   late     wake-up time − deadline [s] (the jitter; 0 on the virtual clock)
//   compute  wall time of Session::Step() [s]
// A tick is a MISS when it starts later than `miss_tolerance` after its deadline (the loop then
// runs at once: it catches up, it does not skip); an OVERRUN when its step takes longer than h.
// After `hold_after_misses` consecutive misses the run is held (RequestStop: every actuator
// holds at its last command, resumable), and so is a run whose observers' queue is nearly
// full on the wall clock (SetQueue): the files cannot keep up, the loop does not wait. The tracking criteria J1–J3 of every actuator and
// every physical slot (runner/tracking_set.h) are kept live (J1 over the last second, one
// actuator or slot per tick of every kLiveJ1Every). Everything goes into the sidecar's
// statistics as `real_time` (AddStatistics).
//
// Needs a scheme with one specimen evaluation per fixed step whose command is known before
// that step's measurement: α-OS without adaptive step (schemes/alpha_os.h). Refused with
// ConfigError otherwise.
#include <chrono>
#include <string>
#include <vector>

#include "hybridtest/common/clock.h"
#include "hybridtest/runner/lock_free_observer.h"
#include "hybridtest/runner/session.h"
#include "hybridtest/runner/tracking_set.h"

namespace hybridtest::runner {

struct PacedStatistics {
  long ticks = 0;
  long misses = 0;
  long overruns = 0;
  long max_consecutive_misses = 0;
  bool held_on_misses = false;
  bool held_on_queue = false;
  std::size_t queue_min_free = 0;  // the fewest free events seen in the queue (0: no queue)
  long queue_waits = 0;            // virtual clock: ticks that waited for the queue
  double late_p50 = 0.0, late_p99 = 0.0, late_max = 0.0;           // [s]
  double compute_p50 = 0.0, compute_p99 = 0.0, compute_max = 0.0;  // [s]
};

class PacedLoop final : public SessionObserver, public StepPacer {
 public:
  // StepPacer.
  void Start() override;
  void BeforeStep(bool after_hold) override;
  void AfterStep(const StepResult& result) override;
  // Its counts, this tick's lateness, the tick before's compute time, the criteria of every
  // actuator now and the delay its compensator removes (read from the physical substructures'
  // transfer systems here, on the stepping thread; preallocated: nothing is allocated).
  const RealTimeSample* Sample() override;

  const PacedStatistics& statistics() const { return stats_; }
  // The first actuator's criteria (the run's J1–J3 before there were several) and every one's.
  const TrackingCriteria& criteria() const {
    return tracking_.num_actuators() > 0 ? tracking_.actuator(0) : no_actuator_;
  }
  const TrackingSet& tracking() const { return tracking_; }
  // Ticks between two live J1 updates (each updates one actuator or slot).
  static constexpr long kLiveJ1Every = 64;
  // For the live monitor, read on the stepping thread during a step: the clock's name, this
  // tick's lateness [s], the compute time of the tick before it [s] (this tick's step is still
  // going) and the missed deadlines in a row now.
  std::string clock_name() const { return clock_.name(); }
  double tick_late() const { return i_ < late_.size() ? late_[i_] : 0.0; }
  double previous_compute() const {
    return i_ > 0 && i_ - 1 < compute_.size() ? compute_[i_ - 1] : 0.0;
  }
  // What the process setup did (memory lock, scheduling, affinity), for the sidecar.
  void AddSetupNote(std::string note) { setup_notes_.push_back(std::move(note)); }
  // The delay stability check's margins (delay_stability.h), for the sidecar.
  void SetStability(nlohmann::json margins) { stability_ = std::move(margins); }
  // The queue the other observers drain (lock_free_observer.h): when fewer than kQueueReserve
  // events still fit, the loop holds the run on the wall clock (it never waits there, and the
  // queue never fills) and waits for the queue on the virtual clock (no deadline to miss; the
  // run stays bit-reproducible). Not owned.
  void SetQueue(LockFreeObserver* queue) { queue_ = queue; }
  nlohmann::json ToJson() const;

  void OnTrial(const TrialEvent& event) override;
  void AddStatistics(nlohmann::json& statistics) override;
  bool real_time_safe() const override { return true; }

 private:
  // Built by the Session from its spec (Session::BuildPacer), never by a front: adds itself to
  // the session's observers; `clock` must outlive the loop. Throws ConfigError when the
  // session's scheme or a physical substructure's transfer system cannot run paced (nothing
  // has moved).
  friend class Session;
  PacedLoop(Session& session, Clock& clock);
  void Summarise();

  Session& session_;
  Clock& clock_;
  double tick_;
  double miss_tolerance_;
  long hold_after_;
  bool paced_ = false;
  double t0_ = 0.0;       // the deadlines' origin [s] on the clock
  long k_ = 0;            // the tick
  long consecutive_ = 0;  // consecutive misses
  std::size_t i_ = 0;     // the tick's index into late_, compute_
  std::chrono::steady_clock::time_point step_start_;
  LockFreeObserver* queue_ = nullptr;
  PacedStatistics stats_;
  TrackingSet tracking_;
  TrackingCriteria no_actuator_;  // criteria() of a run without a physical actuator
  std::vector<double> late_, compute_;  // per tick, preallocated
  RealTimeSample sample_;
  // (actuators), sized by the constructor
  std::vector<double> sample_J1_, sample_J2_, sample_J3_, sample_delay_;
  std::vector<std::string> setup_notes_;
  nlohmann::json stability_ = nlohmann::json::array();
};

}  // namespace hybridtest::runner
