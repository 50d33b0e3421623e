#pragma once
// Decimation for plotting that keeps the extremes of a line.
//
// A line with more than max_points samples is split into (max_points - 2)/4 contiguous buckets of
// (almost) equal sample count; from each bucket the samples holding the minimum and maximum of
// y and the minimum and maximum of x are kept, in their original order (for a time history x is
// time, so those are simply the bucket's first and last samples). The first and last sample of
// the line are always kept. So at most max_points samples remain, every peak and trough of the
// line survives exactly, and a hysteresis loop (force against displacement) keeps its corners.
// Lines with at most max_points samples are returned whole. Decimation only ever affects what
// is drawn; statistics (compare.h) always use every sample.
#include <Eigen/Core>

#include <vector>

namespace hybridtest::report {

// Lines longer than this are decimated before they are handed to gnuplot. Unit: [samples]
inline constexpr Eigen::Index kMaxPlotPoints = 20000;

// Indices (ascending, unique) of the samples to draw. x and y must have the same length;
// max_points must be at least 8.
std::vector<Eigen::Index> SelectPlotSamples(const Eigen::VectorXd& x, const Eigen::VectorXd& y,
                                            Eigen::Index max_points = kMaxPlotPoints);

}  // namespace hybridtest::report
