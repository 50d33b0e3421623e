#pragma once
// TrackingCriteria: the vRTHS benchmark's tracking criteria (Silva et al. 2020) of one
// actuator, from its command x_c and measured position x_m sampled once per tick:
//
//   J1  tracking delay: the lag of the peak of the cross-correlation of x_m against x_c (the
//       correlation coefficient over the overlap at each lag,
//       searched over 0 … max_lag, refined by a parabola through the peak). Unit: [ms]
//   J2  normalised RMS tracking error  σ(x_m − x_c) / σ(x_c) · 100. Unit: [%]
//   J3  peak tracking error  max|x_m − x_c| / max|x_c| · 100. Unit: [%]
//
// J2 and J3 are kept live (running sums, O(1) per sample); J1 is computed at the end. Samples
// go into preallocated storage: Add() never allocates (samples past the capacity only enter
// J2 and J3).
#include <nlohmann/json.hpp>

#include <vector>

namespace hybridtest::runner {

class TrackingCriteria {
 public:
  // capacity: samples kept for J1; tick: sampling interval [s]; max_lag: the longest delay
  // looked for [s].
  void Reserve(long capacity, double tick, double max_lag = 0.2);
  void Add(double command, double measured);

  long samples() const { return n_; }
  double J1_ms() const;
  // J1 over the last `window` samples kept (at most), for a live estimate. Unit: [ms]
  double J1_ms(long window) const;
  double J2() const;
  double J3() const;
  // {J1_ms, J2, J3, samples} (null where undefined).
  nlohmann::json ToJson() const;

 private:
  std::vector<double> xc_, xm_;
  double tick_ = 0.0, max_lag_ = 0.0;
  long n_ = 0;
  double sc_ = 0.0, scc_ = 0.0, se_ = 0.0, see_ = 0.0, emax_ = 0.0, cmax_ = 0.0;
};

}  // namespace hybridtest::runner
