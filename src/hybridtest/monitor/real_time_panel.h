#pragma once
// RealTimePanel: what the monitor's "Real time" panel shows of a paced run (docs/real-time.md),
// live from the per-tick columns of the frames (FrameLayout::rt) and, once the run has ended,
// as the sidecar records it (statistics.real_time: the exact percentiles and J1).
//
// Live, per frame (one frame per tick of a paced run): ticks, missed deadlines (total, in a row
// now, most in a row), overruns, the tick's lateness [s], the previous tick's compute time [s],
// J2 and J3 [%] of the first physical actuator (runner/tracking_criteria.h), the current
// delay estimate [s] of each compensated actuator, then J1 (a running estimate over the last second)
// [ms], J2 and J3 [%] of every physical actuator (runner/tracking_set.h). Lateness and compute percentiles are over every
// tick received, from a histogram of logarithmic bins 5 % wide (bounded memory on a run of
// any length; a percentile is its bin's upper edge, the maximum is exact). Frames the ring
// dropped are missing from the percentiles, never from the counts (which are the loop's own).
//
// Json() has the keys of the sidecar's statistics.real_time where they mean the same
// (ticks, misses, overruns, max_consecutive_misses, hold_after_misses, late_s, compute_s,
// J1_ms, J2, J3, compensation, actuators: [{name, J1_ms, J2, J3}]), plus available, source ("live" or "recorded") and
// misses_in_a_row (live only) and paced (a real-time run, even before anything is known).
// Live, compensation is {substructure: {delay_s: the smallest of its actuators' estimates,
// actuators: [{name, delay_s}]}}, one entry per actuator as in the sidecar's record.
#include <nlohmann/json.hpp>

#include <array>
#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace hybridtest::monitor {

// Per-tick columns of a real-time frame, in this order, then one compensated delay [s] per
// compensated actuator (RealTimeSetup::compensators, in order), then J1 [ms], J2 and J3 [%]
// per actuator (RealTimeSetup::actuators).
enum RealTimeColumn : int {
  kRtTicks, kRtMisses, kRtMissesInARow, kRtMaxInARow, kRtOverruns, kRtLate, kRtCompute,
  kRtJ2, kRtJ3, kRtColumns
};

// A physical substructure whose transfer system compensates delay, and its actuators (journal
// names), one delay estimate each.
struct CompensatedBlock {
  std::string name;
  std::vector<std::string> actuators;
};

// What is known of a paced run before it starts.
struct RealTimeSetup {
  bool enabled = false;
  std::string clock;                     // "wall" or "virtual" ("" if not known)
  double tick = 0.0;                     // [s]
  long hold_after_misses = 0;            // 0: never holds on misses
  std::vector<CompensatedBlock> compensators;  // one delay column per actuator of each
  std::vector<std::string> actuators;     // every physical actuator (journal names), J1–J3 each
  bool live = true;  // the frames carry the per-tick columns (false: a followed journal, whose
                     // statistics are its sidecar's once it has ended)
};

// Percentiles of non-negative durations from logarithmic bins (1e-7 s … ~30 s, 5 % wide).
class DurationHistogram {
 public:
  void Add(double seconds);
  double Percentile(double p) const;  // p in [0, 1]; 0 without samples. Unit: [s]
  double max() const { return max_; }
  long count() const { return count_; }

 private:
  static constexpr int kBins = 400;
  std::array<long, kBins> bins_{};
  long count_ = 0;
  double max_ = 0.0;
};

class RealTimePanel {
 public:
  void Configure(RealTimeSetup setup);
  bool enabled() const { return setup_.enabled; }
  std::size_t columns() const {
    return enabled() && setup_.live
               ? kRtColumns + compensated_actuators() + 3 * setup_.actuators.size()
               : 0;
  }
  // The real-time columns of one frame (columns() values).
  void Add(std::span<const double> columns);
  // The run's own record (the sidecar's statistics.real_time) once it has ended.
  void SetRecorded(nlohmann::json record);
  nlohmann::json Json() const;

 private:
  std::size_t compensated_actuators() const;
  nlohmann::json LiveCompensation() const;

  RealTimeSetup setup_;
  std::vector<double> last_;
  DurationHistogram late_, compute_;
  nlohmann::json recorded_;
};

}  // namespace hybridtest::monitor
