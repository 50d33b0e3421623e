#pragma once
// The error measures of the vRTHS benchmark (Silva et al. 2020) on two sampled signals, a
// signal x against a target y (the same number of samples, one sampling interval):
//
//   TrackingDelayMs   the lag of the peak of the cross-correlation of x against y: at each
//                     lag L = 0 … max_lag/tick the correlation coefficient of y(i) and
//                     x(i + L) over their overlap, the best L refined by a parabola through the
//                     peak and its neighbours. Unit: [ms]
//   NormalisedRmsError σ(x − y) / σ(y) · 100, σ the standard deviation. Unit: [%]
//   PeakError          max|x − y| / max|y| · 100. Unit: [%]
//
// NaN where undefined (too few samples, a constant or zero target). The benchmark's J1–J3
// apply them to an actuator's measured position against its command, J4–J9 to a run's
// responses against the reference structure's (report/rths_criteria.h).
#include <span>

namespace hybridtest {

double TrackingDelayMs(std::span<const double> x, std::span<const double> y, double tick,
                       double max_lag);
double NormalisedRmsError(std::span<const double> x, std::span<const double> y);
double PeakError(std::span<const double> x, std::span<const double> y);

}  // namespace hybridtest
