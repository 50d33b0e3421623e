// Comparison statistics against hand-computed values on synthetic runs.
#include "hybridtest/report/compare.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>

#include "hybridtest/common/error.h"
#include "hybridtest/report/compare_plot.h"
#include "report/plot_test_runs.h"

namespace hybridtest::report {
namespace {

using testing::ScratchDir;
using testing::Slurp;

// A run with channels t, q1 [m] and u1 [m/s] sampled at t_k = t0 + k dt, k = 0..n-1.
io::RunData SineRun(const std::string& path, double t0, double dt, int n,
                    const std::function<double(double)>& q) {
  Eigen::MatrixXd v(n, 3);
  for (int k = 0; k < n; ++k) {
    const double t = t0 + k * dt;
    v(k, 0) = t;
    v(k, 1) = q(t);
    v(k, 2) = -q(t);
  }
  testing::WriteRunFiles(path, {{"t", "s", "time"}, {"q1", "m", "x"}, {"u1", "m/s", "v"}}, v,
                         nlohmann::json{{"model", {{"name", "oscillator"}}}});
  return io::LoadRun(path);
}

constexpr double kTwoPi = 2.0 * M_PI;

TEST(CompareRuns, TwoSinesWithKnownOffsetAndAmplitude) {
  const ScratchDir dir("compare-sines");
  // A = 1 + 2 sin(2π t), B = 0.5 + sin(2π t), both on t = 0, 0.001, ..., 10 s.
  const io::RunData a = SineRun(dir / "a.csv", 0, 1e-3, 10001,
                                [](double t) { return 1.0 + 2.0 * std::sin(kTwoPi * t); });
  const io::RunData b = SineRun(dir / "b.csv", 0, 1e-3, 10001,
                                [](double t) { return 0.5 + std::sin(kTwoPi * t); });
  EXPECT_DOUBLE_EQ(DefaultTransient(a), 3.0);
  const ComparisonTable table = CompareRuns(a, b, DefaultTransient(a));
  EXPECT_EQ(table.name_a, "a");
  EXPECT_EQ(table.name_b, "b");
  EXPECT_EQ(table.compared_points, 10001);
  EXPECT_EQ(table.interpolated_points, 0);
  ASSERT_EQ(table.rows.size(), 2u);
  const ChannelComparison& q = table.rows[0];
  EXPECT_EQ(q.channel, "q1");
  EXPECT_EQ(q.unit, "m");
  // A − B = 0.5 + sin: max 1.5; over whole periods (sin sums to 0, sin² to N/2, the grid's
  // end points have sin = 0): RMS² = 0.25 + 5000/10001.
  EXPECT_NEAR(q.max_abs_diff, 1.5, 1e-9);
  EXPECT_NEAR(q.rms_diff, std::sqrt(0.25 + 5000.0 / 10001.0), 1e-9);
  // After 3 s: 7 whole periods.
  EXPECT_NEAR(q.mean_a, 1.0, 1e-9);
  EXPECT_NEAR(q.amplitude_a, 2.0, 1e-9);
  EXPECT_NEAR(q.mean_b, 0.5, 1e-9);
  EXPECT_NEAR(q.amplitude_b, 1.0, 1e-9);
  // u1 = −q1.
  EXPECT_NEAR(table.rows[1].mean_a, -1.0, 1e-9);
  EXPECT_NEAR(table.rows[1].max_abs_diff, 1.5, 1e-9);
}

TEST(CompareRuns, TransientSelectsTheSteadyWindow) {
  const ScratchDir dir("compare-transient");
  // A ramps from 0 to 10 over 10 s; after 8 s its mean is 9 and its amplitude 1.
  const io::RunData a = SineRun(dir / "a.csv", 0, 0.5, 21, [](double t) { return t; });
  const ComparisonTable table = CompareRuns(a, a, 8.0);
  EXPECT_DOUBLE_EQ(table.rows[0].mean_a, 9.0);
  EXPECT_DOUBLE_EQ(table.rows[0].amplitude_a, 1.0);
  EXPECT_EQ(table.rows[0].max_abs_diff, 0.0);
  EXPECT_THROW(CompareRuns(a, a, 10.5), ConfigError);
  EXPECT_THROW(CompareRuns(a, a, -1.0), ConfigError);
}

TEST(CompareRuns, DifferentGridsInterpolateBLinearlyOntoA) {
  const ScratchDir dir("compare-grids");
  // Linear signals, so linear interpolation is exact: A − B = −0.25 everywhere.
  const io::RunData a = SineRun(dir / "a.csv", 0, 1e-3, 2001, [](double t) { return 3 * t; });
  const io::RunData b =
      SineRun(dir / "b.csv", 0.0007, 0.0023, 700, [](double t) { return 3 * t + 0.25; });
  const ComparisonTable table = CompareRuns(a, b, 0.0);
  // A's points inside [0.0007, 0.0007 + 699·0.0023 = 1.6084]: t = 0.001 .. 1.608.
  EXPECT_EQ(table.compared_points, 1608);
  EXPECT_GT(table.interpolated_points, 1000);
  EXPECT_NEAR(table.rows[0].max_abs_diff, 0.25, 1e-12);
  EXPECT_NEAR(table.rows[0].rms_diff, 0.25, 1e-12);
}

TEST(CompareRuns, RefusesRunsThatCannotBeCompared) {
  const ScratchDir dir("compare-refuse");
  const io::RunData a = SineRun(dir / "a.csv", 0, 0.1, 11, [](double t) { return t; });
  const io::RunData later = SineRun(dir / "later.csv", 5, 0.1, 11, [](double t) { return t; });
  EXPECT_THROW(CompareRuns(a, later, 0.0), IoError);
  Eigen::MatrixXd v(3, 2);
  v << 0, 1, 0.1, 2, 0.2, 3;
  testing::WriteRunFiles(dir / "other.csv", {{"t", "s", ""}, {"x9", "m", ""}}, v, nullptr);
  EXPECT_THROW(CompareRuns(a, io::LoadRun(dir / "other.csv"), 0.0), IoError);
}

TEST(CompareRuns, TextAndCsvHoldEveryRowWithUnits) {
  const ScratchDir dir("compare-output");
  const io::RunData a = SineRun(dir / "a.csv", 0, 0.01, 101, [](double t) { return t; });
  const io::RunData b = SineRun(dir / "b.csv", 0, 0.01, 101, [](double t) { return 2 * t; });
  const ComparisonTable table = CompareRuns(a, b, 0.3);
  const std::string text = FormatComparisonText(table);
  EXPECT_NE(text.find("max|A-B|"), std::string::npos);
  EXPECT_NE(text.find("[m/s]"), std::string::npos);
  WriteComparisonCsv(table, dir / "cmp.csv");
  const std::string csv = Slurp(dir / "cmp.csv");
  EXPECT_EQ(csv.rfind("channel,unit,max_abs_diff,rms_diff,mean_a,amplitude_a,mean_b,amplitude_b\n",
                      0),
            0u);
  EXPECT_NE(csv.find("\nq1,m,1,"), std::string::npos);  // max |t − 2t| = 1 at t = 1
  EXPECT_NE(csv.find("\nu1,m/s,"), std::string::npos);
}

TEST(DistinctRunNames, UsesTheParentDirectoryWhenStemsAgree) {
  const ScratchDir dir("compare-names");
  std::filesystem::create_directories(dir / "hybrid");
  std::filesystem::create_directories(dir / "numerical");
  const io::RunData a = SineRun(dir / "hybrid/run.csv", 0, 0.1, 11, [](double t) { return t; });
  const io::RunData b = SineRun(dir / "numerical/run.csv", 0, 0.1, 11, [](double t) { return t; });
  const auto [na, nb] = DistinctRunNames(a, b);
  EXPECT_EQ(na, "hybrid/run");
  EXPECT_EQ(nb, "numerical/run");
}

TEST(CompareCommand, PrintsTheTableAndWritesCsvAndOverlayFigures) {
  const ScratchDir dir("compare-cli");
  testing::RotorRunSpec hybrid;
  const std::string a = testing::WriteRotorRun(dir.path(), hybrid);
  testing::RotorRunSpec numerical;
  numerical.name = "numerical";
  numerical.physical_r1 = false;
  numerical.q1_offset = 0.0;
  const std::string b = testing::WriteRotorRun(dir.path(), numerical);
  const std::string command = fmt::format("'{}' compare '{}' '{}' --out '{}' > '{}'",
                                          HYBRIDTEST_BINARY, a, b, dir / "cmp", dir / "out.txt");
  ASSERT_EQ(std::system(command.c_str()), 0);
  const std::string out = Slurp(dir / "out.txt");
  EXPECT_NE(out.find("A = hybrid"), std::string::npos);
  EXPECT_NE(out.find("q1"), std::string::npos);
  const std::string csv = Slurp(dir / "cmp/comparison.csv");
  EXPECT_NE(csv.find("\nq4,rad,"), std::string::npos);
  EXPECT_EQ(csv.find("r1_force"), std::string::npos);  // only in A
  // The paper's finding, on the synthetic runs: q1 of the hybrid run has the larger mean.
  const io::RunData ra = io::LoadRun(a), rb = io::LoadRun(b);
  const ComparisonTable table = CompareRuns(ra, rb, DefaultTransient(ra));
  EXPECT_NEAR(table.rows[0].mean_a - table.rows[0].mean_b, 0.02, 1e-3);
  const std::string svg = Slurp(dir / "cmp/compare-displacements.svg");
  EXPECT_NE(svg.find("hybrid (physical)"), std::string::npos);
  EXPECT_NE(svg.find(">numerical<"), std::string::npos);
  EXPECT_GT(Slurp(dir / "cmp/compare-hub-speed.png").size(), 5000u);
}

// A multi-rate run: rows every 0.1 s, but the specimen's force r1_force only every row up to
// 5 s and every 10th row after. f = 1 up to 5 s, 3 after; B's force is A's plus d, d = 1 up
// to 5 s and 2 after; r1_lab_time is a clock.
io::RunData SparseRun(const std::string& path, bool b) {
  const int n = 101;
  Eigen::MatrixXd v(n, 3);
  for (int k = 0; k < n; ++k) {
    const double t = 0.1 * k;
    const bool sampled = k <= 50 || k % 10 == 0;
    const double f = k <= 50 ? 1.0 : 3.0;
    const double d = k <= 50 ? 1.0 : 2.0;
    v(k, 0) = t;
    v(k, 1) = sampled ? f + (b ? d : 0.0) : NAN;
    v(k, 2) = sampled ? 1.13 * k : NAN;
  }
  testing::WriteRunFiles(path, {{"t", "s", "time"}, {"r1_force", "N", "force"},
                                {"r1_lab_time", "s", "lab time"}},
                         v, nlohmann::json{{"model", {{"name", "mr-os"}}}});
  return io::LoadRun(path);
}

TEST(CompareRuns, SparseChannelsAreWeightedByTimeAndClocksHaveNoLevel) {
  const ScratchDir dir("compare-sparse");
  const io::RunData a = SparseRun(dir / "a.csv", false);
  const io::RunData b = SparseRun(dir / "b.csv", true);
  const ComparisonTable table = CompareRuns(a, b, 0.0);
  ASSERT_EQ(table.rows.size(), 2u);
  const ChannelComparison& f = table.rows[0];
  // Trapezoid over the samples A has: 5·1 + (1+3)/2·1 + 4·3 = 19 over 10 s. Counting samples
  // would give (51·1 + 5·3)/56 = 1.18.
  EXPECT_NEAR(f.mean_a, 1.9, 1e-12);
  EXPECT_NEAR(f.amplitude_a, 1.0, 1e-12);
  // d²: 5·1 + (1+4)/2·1 + 4·4 = 23.5 over 10 s.
  EXPECT_NEAR(f.rms_diff, std::sqrt(2.35), 1e-12);
  EXPECT_NEAR(f.max_abs_diff, 2.0, 1e-12);
  const ChannelComparison& clock = table.rows[1];
  EXPECT_EQ(clock.channel, "r1_lab_time");
  EXPECT_TRUE(std::isnan(clock.mean_a) && std::isnan(clock.amplitude_a));
  EXPECT_TRUE(std::isnan(clock.mean_b) && std::isnan(clock.amplitude_b));
  EXPECT_EQ(clock.max_abs_diff, 0.0);
  const std::string text = FormatComparisonText(table);
  EXPECT_EQ(text.find("nan"), std::string::npos) << text;
}

}  // namespace
}  // namespace hybridtest::report
