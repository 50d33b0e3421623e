#include "hybridtest/report/compare.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <filesystem>
#include <fstream>

#include "hybridtest/common/error.h"
#include "hybridtest/report/plot.h"
#include "hybridtest/report/plot_layout.h"

namespace hybridtest::report {
namespace {

constexpr double kTimeMatchTolerance = 1e-12;  // [s]

void CheckIncreasing(const io::RunData& run, const Eigen::VectorXd& t) {
  for (Eigen::Index i = 1; i < t.size(); ++i) {
    if (!(t[i] > t[i - 1])) {
      throw IoError(fmt::format("{}: expected strictly increasing t, found t = {:.17g} s at row "
                                "{} after {:.17g} s; is the CSV a single run?",
                                run.csv_path, t[i], i + 2, t[i - 1]));
    }
  }
}

// Where B is sampled for each compared A point: B index j and weight w, value = (1−w) B[j] +
// w B[j+1] (w = 0 for an exact match).
struct Sample {
  Eigen::Index a;
  Eigen::Index j;
  double w;
};

std::vector<Sample> AlignOnA(const Eigen::VectorXd& ta, const Eigen::VectorXd& tb) {
  std::vector<Sample> samples;
  Eigen::Index j = 0;
  const Eigen::Index nb = tb.size();
  for (Eigen::Index i = 0; i < ta.size(); ++i) {
    const double t = ta[i];
    if (t < tb[0] - kTimeMatchTolerance || t > tb[nb - 1] + kTimeMatchTolerance) continue;
    while (j + 1 < nb && tb[j + 1] <= t + kTimeMatchTolerance) ++j;
    if (std::abs(tb[j] - t) <= kTimeMatchTolerance || j + 1 == nb) {
      samples.push_back({i, j, 0.0});
    } else {
      samples.push_back({i, j, (t - tb[j]) / (tb[j + 1] - tb[j])});
    }
  }
  return samples;
}

// Trapezoid weights of the finite samples listed in `index` (times t): half the time to the
// previous plus half the time to the next finite sample. Σ w v is then the integral of the
// piecewise-linear line through the samples.
std::vector<double> TimeWeights(const Eigen::VectorXd& t, const std::vector<Eigen::Index>& index) {
  std::vector<double> w(index.size(), 0.0);
  for (std::size_t k = 0; k + 1 < index.size(); ++k) {
    const double half = 0.5 * (t[index[k + 1]] - t[index[k]]);
    w[k] += half;
    w[k + 1] += half;
  }
  if (index.size() == 1) w[0] = 1.0;
  return w;
}

// Mean and half range of v over the finite samples with t ≥ t_from. A sparse channel (some
// rows NaN) is averaged over time, each sample weighted by the time it stands for; a dense
// one by sample.
std::pair<double, double> SteadyStats(const Eigen::VectorXd& t, const Eigen::VectorXd& v,
                                      double t_from) {
  std::vector<Eigen::Index> finite;
  bool sparse = false;
  for (Eigen::Index i = 0; i < t.size(); ++i) {
    if (t[i] < t_from) continue;
    if (std::isfinite(v[i])) {
      finite.push_back(i);
    } else {
      sparse = true;  // rows without the quantity
    }
  }
  if (finite.empty()) return {NAN, NAN};
  const std::vector<double> w =
      sparse ? TimeWeights(t, finite) : std::vector<double>(finite.size(), 1.0);
  double sum = 0, weight = 0, lo = INFINITY, hi = -INFINITY;
  for (std::size_t k = 0; k < finite.size(); ++k) {
    const double x = v[finite[k]];
    sum += w[k] * x;
    weight += w[k];
    lo = std::min(lo, x);
    hi = std::max(hi, x);
  }
  return {weight > 0 ? sum / weight : NAN, 0.5 * (hi - lo)};
}

// A lab-time channel is a clock: its level and swing say nothing about the test.
bool IsClock(const std::string& channel) { return channel.ends_with("_lab_time"); }

void CheckWindow(const io::RunData& run, const Eigen::VectorXd& t, double transient,
                 const char* which) {
  if (t[t.size() - 1] < t[0] + transient) {
    throw ConfigError(fmt::format(
        "transient = {} s leaves no samples of run {} ({}), which lasts {} s; give "
        "--transient smaller than the run's duration",
        transient, which, run.csv_path, t[t.size() - 1] - t[0]));
  }
}

}  // namespace

std::pair<std::string, std::string> DistinctRunNames(const io::RunData& a, const io::RunData& b) {
  std::string na = RunName(a), nb = RunName(b);
  if (na != nb) return {na, nb};
  auto with_parent = [](const io::RunData& r) {
    const std::filesystem::path p(r.csv_path);
    const std::string parent = p.parent_path().filename().string();
    return parent.empty() ? p.stem().string() : parent + "/" + p.stem().string();
  };
  na = with_parent(a);
  nb = with_parent(b);
  if (na != nb) return {na, nb};
  return {na + " (A)", nb + " (B)"};
}

double DefaultTransient(const io::RunData& a) {
  const Eigen::VectorXd t = RunTime(a);
  return 0.3 * (t[t.size() - 1] - t[0]);
}

ComparisonTable CompareRuns(const io::RunData& a, const io::RunData& b, double transient) {
  if (!(transient >= 0) || !std::isfinite(transient)) {
    throw ConfigError(fmt::format("transient = {} s: expected a duration ≥ 0 in seconds",
                                  transient));
  }
  const Eigen::VectorXd ta = RunTime(a), tb = RunTime(b);
  CheckIncreasing(a, ta);
  CheckIncreasing(b, tb);
  CheckWindow(a, ta, transient, "A");
  CheckWindow(b, tb, transient, "B");

  ComparisonTable table;
  std::tie(table.name_a, table.name_b) = DistinctRunNames(a, b);
  table.path_a = a.csv_path;
  table.path_b = b.csv_path;
  table.transient = transient;

  // A's time points inside B's span, and how B is read at each.
  const std::vector<Sample> samples = AlignOnA(ta, tb);
  if (samples.empty()) {
    throw IoError(fmt::format("cannot compare {} (t = {} .. {} s) with {} (t = {} .. {} s): the "
                              "runs do not overlap in time",
                              a.csv_path, ta[0], ta[ta.size() - 1], b.csv_path, tb[0],
                              tb[tb.size() - 1]));
  }
  table.compared_points = static_cast<long>(samples.size());
  table.interpolated_points =
      std::count_if(samples.begin(), samples.end(), [](const Sample& s) { return s.w != 0.0; });

  // One row per common channel.
  for (const io::Channel& channel : a.channels) {
    if (channel.name == "t" || FindChannel(b, channel.name) < 0) continue;
    const Eigen::VectorXd va = ChannelValues(a, channel.name);
    const Eigen::VectorXd vb = ChannelValues(b, channel.name);
    ChannelComparison row;
    row.channel = channel.name;
    row.unit = channel.unit;
    // Rows where a run has no such value (NaN: a substep without a specimen sample, a failed
    // trial) are not compared; when there are such rows, each difference is weighted by the
    // time it stands for.
    std::vector<Eigen::Index> rows;
    std::vector<double> diffs;
    bool sparse = false;
    for (const Sample& s : samples) {
      const double b_value = s.w == 0.0 ? vb[s.j] : (1 - s.w) * vb[s.j] + s.w * vb[s.j + 1];
      const double d = va[s.a] - b_value;
      if (!std::isfinite(d)) {
        sparse = true;
        continue;
      }
      row.max_abs_diff = std::max(row.max_abs_diff, std::abs(d));
      rows.push_back(s.a);
      diffs.push_back(d);
    }
    const std::vector<double> w =
        sparse ? TimeWeights(ta, rows) : std::vector<double>(rows.size(), 1.0);
    double sum_sq = 0, weight = 0;
    for (std::size_t k = 0; k < diffs.size(); ++k) {
      sum_sq += w[k] * diffs[k] * diffs[k];
      weight += w[k];
    }
    row.rms_diff = weight > 0 ? std::sqrt(sum_sq / weight)
                              : std::numeric_limits<double>::quiet_NaN();
    if (IsClock(channel.name)) {
      row.mean_a = row.amplitude_a = row.mean_b = row.amplitude_b = NAN;
    } else {
      std::tie(row.mean_a, row.amplitude_a) = SteadyStats(ta, va, ta[0] + transient);
      std::tie(row.mean_b, row.amplitude_b) = SteadyStats(tb, vb, tb[0] + transient);
    }
    table.rows.push_back(row);
  }
  if (table.rows.empty()) {
    throw IoError("cannot compare " + a.csv_path + " with " + b.csv_path +
                  ": they have no channel in common besides t");
  }
  return table;
}

std::string FormatComparisonText(const ComparisonTable& table) {
  std::string out;
  out += fmt::format("A = {} ({})\nB = {} ({})\n", table.name_a, table.path_a, table.name_b,
                     table.path_b);
  out += fmt::format(
      "A - B at {} of A's time points ({} with B interpolated linearly, the rest exact); mean "
      "and amplitude after the first {:.6g} s\n\n",
      table.compared_points, table.interpolated_points, table.transient);
  std::size_t name_width = 7, unit_width = 4;
  for (const ChannelComparison& row : table.rows) {
    name_width = std::max(name_width, row.channel.size());
    unit_width = std::max(unit_width, row.unit.size() + 2);
  }
  out += fmt::format("{:<{}} {:<{}} {:>13} {:>13} {:>13} {:>13} {:>13} {:>13}\n", "channel",
                     name_width, "unit", unit_width, "max|A-B|", "RMS(A-B)", "mean A", "amp A",
                     "mean B", "amp B");
  const auto cell = [](double v) {
    return std::isnan(v) ? fmt::format("{:>13}", "-") : fmt::format("{:>13.6g}", v);
  };
  for (const ChannelComparison& row : table.rows) {
    out += fmt::format("{:<{}} {:<{}} {} {} {} {} {} {}\n", row.channel, name_width,
                       "[" + row.unit + "]", unit_width, cell(row.max_abs_diff),
                       cell(row.rms_diff), cell(row.mean_a), cell(row.amplitude_a),
                       cell(row.mean_b), cell(row.amplitude_b));
  }
  return out;
}

void WriteComparisonCsv(const ComparisonTable& table, const std::string& csv_path) {
  std::ofstream out(csv_path);
  if (!out) {
    throw IoError("cannot write the comparison table to " + csv_path +
                  "; check that the directory exists and is writable");
  }
  out << "channel,unit,max_abs_diff,rms_diff,mean_a,amplitude_a,mean_b,amplitude_b\n";
  for (const ChannelComparison& row : table.rows) {
    out << fmt::format("{},{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n", row.channel,
                       row.unit, row.max_abs_diff, row.rms_diff, row.mean_a, row.amplitude_a,
                       row.mean_b, row.amplitude_b);
  }
  out.flush();
  if (!out) throw IoError("write failed for " + csv_path);
}

}  // namespace hybridtest::report
