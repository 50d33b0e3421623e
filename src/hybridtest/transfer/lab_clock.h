#pragma once
// LabClock: the lab time an emulated bench would take, accumulated phase by phase.
// Accelerated (default): only counts. Realtime: Pace() sleeps until the wall time since Start()
// has caught up with the lab time, so a run takes as long as the real test would.
#include <chrono>

namespace hybridtest::transfer {

class LabClock {
 public:
  explicit LabClock(bool realtime) : realtime_(realtime) {}

  // Sets the wall-clock origin; later calls do nothing (lab time continues across holds).
  void Start();
  // Adds `duration` [s] of lab time.
  void Advance(double duration) { lab_time_ += duration; }
  // Realtime: sleeps until wall time since Start() ≥ lab time. Accelerated: returns at once.
  void Pace() const;

  double lab_time() const { return lab_time_; }  // Unit: [s].
  // Sets the lab time [s] (a checkpoint's); a realtime clock paces on from there.
  void Restore(double lab_time);
  bool realtime() const { return realtime_; }

 private:
  bool realtime_;
  bool started_ = false;
  double lab_time_ = 0.0;
  std::chrono::steady_clock::time_point origin_{};
};

}  // namespace hybridtest::transfer
