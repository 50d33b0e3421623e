#pragma once
// Comparison of two runs channel by channel, e.g. the hybrid test against the pure numerical
// simulation (the paper's Fig. 6 against Fig. 7).
//
// Time grids. Differences A − B are evaluated at A's time points that lie inside B's time span
// (no extrapolation). Where a B time point lies within 1e-12 s of A's, B's sample is used as is
// (so identical grids compare sample by sample, with no interpolation error); elsewhere B is
// interpolated linearly between its neighbouring samples.
//
// Steady window. Means and amplitudes describe each run on its own samples (not interpolated)
// with t ≥ t_first + transient, i.e. after the initial transient. Amplitude = (max − min) / 2.
// max |A − B| and RMS(A − B) use every compared point, transient included.
//
// Missing values. A NaN sample (a scheme's substep row carries no specimen sample; a failed
// trial has no force) is left out of every statistic; a channel with no finite sample in the
// window reports NaN. A sparse channel (one with such rows) is weighted by time: its mean and
// RMS(A − B) weight each remaining sample by half the time to its finite neighbours (the
// trapezoid rule over the samples it has), so a stretch of rare samples counts for its
// duration, not its sample count. A dense channel is weighted by sample.
//
// Clocks. A `*_lab_time` channel gets no mean and no amplitude (NaN): a clock's level says
// nothing about the test. Its max |A − B| and RMS are kept.
//
// Common channels are those in both runs except t, in A's order.
#include <iosfwd>
#include <string>
#include <vector>

#include "hybridtest/io/run_reader.h"

namespace hybridtest::report {

struct ChannelComparison {
  std::string channel;      // e.g. "q1"
  std::string unit;         // A's unit; every value below is in it
  double max_abs_diff = 0;  // max |A − B| over the compared points
  double rms_diff = 0;      // sqrt(mean((A − B)²)) over the compared points
  double mean_a = 0;        // mean of A in the steady window
  double amplitude_a = 0;   // (max − min)/2 of A in the steady window
  double mean_b = 0;
  double amplitude_b = 0;
};

struct ComparisonTable {
  std::string name_a, name_b;   // run names (plot_layout.h RunName; made distinct)
  std::string path_a, path_b;   // CSV paths
  double transient = 0;         // length of the excluded initial transient. Unit: [s]
  long compared_points = 0;     // A's time points inside B's span
  long interpolated_points = 0; // of those, how many needed interpolation of B
  std::vector<ChannelComparison> rows;
};

// Default transient: 30 % of run A's duration. Unit: [s]
double DefaultTransient(const io::RunData& a);

// Compares a and b as described above. transient in [s], ≥ 0. Throws ConfigError for a
// negative transient or one that leaves no samples in a run, IoError when the runs share no
// channel, do not overlap in time, or a run's t is not increasing.
ComparisonTable CompareRuns(const io::RunData& a, const io::RunData& b, double transient);

// The table as aligned text (a heading that names both runs, the alignment and the window,
// then one line per channel), for a terminal.
std::string FormatComparisonText(const ComparisonTable& table);

// Writes the table as CSV (header: channel,unit,max_abs_diff,rms_diff,mean_a,amplitude_a,
// mean_b,amplitude_b; values with 17 significant digits). Throws IoError on failure.
void WriteComparisonCsv(const ComparisonTable& table, const std::string& csv_path);

// Distinct display names for two runs: their RunName, or, when equal, parent/name, or, when
// still equal, name (A) and name (B).
std::pair<std::string, std::string> DistinctRunNames(const io::RunData& a, const io::RunData& b);

}  // namespace hybridtest::report
