#pragma once
// Planning a real-time test the day before (`hybridtest plan` on a config with a `real_time:`
// block, docs/real-time.md): which delay compensator and which step? Every candidate is the
// configured run paced in virtual time on its emulated plant (never a real bench; nothing is
// written), and reports the tracking criteria J1–J3 of the first physical slot
// (runner/tracking_criteria.h) and the delay stability margin of every physical slot
// (runner/delay_stability.h).
//
// Candidates, for each step (the configured dt and dt/2): the plant alone ("none"), the
// polynomial extrapolation of order 2 over the plant's delay and the adaptive time series
// (ATS) starting from that delay (the configured compensator's settings where it is the same
// method). The plant's delay is the one the stability check finds (its phase delay at the
// crossing frequency). Every candidate runs even where the check predicts it unstable
// (real_time.force): it then grows until a safety limit stops it, which its row says.
//
// Recommendation: among the candidates that finished and that the check finds stable, the one
// with the smallest J2 (then the larger step, the cheaper one).
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace hybridtest::runner {

struct RealTimePlanResult {
  std::string compensator;          // "none", "polynomial" or "ats"
  double dt = 0.0;                  // [s]
  double compensation = 0.0;        // the delay the compensator starts from [s]
  bool ok = false;                  // the run finished
  std::string failure;              // why not
  double J1_ms = 0.0, J2 = 0.0, J3 = 0.0;  // [ms], [%], [%]; NaN where undefined
  double critical_delay = 0.0;      // the smallest τ_c over the physical slots [s]
  double remaining_delay = 0.0;     // the largest delay left after compensation [s]
  bool unstable = false;            // a slot's remaining delay exceeds its τ_c
  long ticks = 0;
  std::string Label() const;        // e.g. "ats, dt 0.977 ms"
};

struct RealTimePlanOptions {
  std::vector<double> dts;          // steps to try [s] (empty: the configured dt and dt/2)
  // Called after each candidate (index, count, result).
  std::function<void(std::size_t, std::size_t, const RealTimePlanResult&)> on_result;
};

// Runs every candidate of the real-time config at `config_path`. Throws ConfigError for a
// config without a `real_time:` block or without a physical slot on an emulated plant
// (`rt_plant`, optionally `compensated`).
std::vector<RealTimePlanResult> PlanRealTime(const std::string& config_path,
                                             const RealTimePlanOptions& options = {});

// The recommendation (see above), if any candidate qualifies.
std::optional<RealTimePlanResult> RecommendRealTime(
    const std::vector<RealTimePlanResult>& results);

// The `transfer:` of the first physical slot and the `integrator.dt` that select `result`, as
// YAML text to paste into the config.
std::string RealTimeCandidateYaml(const std::string& config_path,
                                  const RealTimePlanResult& result);

}  // namespace hybridtest::runner
