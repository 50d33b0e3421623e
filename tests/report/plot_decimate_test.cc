// Decimation keeps every extreme and the ends, and respects the point budget.
#include "hybridtest/report/plot_decimate.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace hybridtest::report {
namespace {

TEST(SelectPlotSamples, ShortLinesAreKeptWhole) {
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(100, 0, 1);
  const auto keep = SelectPlotSamples(x, x, 100);
  ASSERT_EQ(keep.size(), 100u);
  EXPECT_EQ(keep.back(), 99);
}

TEST(SelectPlotSamples, LongLinesKeepPeaksEndsAndOrderWithinBudget) {
  const Eigen::Index n = 200001;
  const Eigen::VectorXd t = Eigen::VectorXd::LinSpaced(n, 0, 20);
  Eigen::VectorXd y = (t.array() * 7.3).sin() * (t.array() * 0.31).cos();
  y[123457] = 50.0;   // a one-sample spike
  y[4242] = -60.0;    // and a one-sample dip
  const auto keep = SelectPlotSamples(t, y, kMaxPlotPoints);
  EXPECT_LE(static_cast<Eigen::Index>(keep.size()), kMaxPlotPoints);
  EXPECT_GT(static_cast<Eigen::Index>(keep.size()), kMaxPlotPoints / 2);
  EXPECT_TRUE(std::is_sorted(keep.begin(), keep.end()));
  EXPECT_EQ(std::adjacent_find(keep.begin(), keep.end()), keep.end());
  EXPECT_EQ(keep.front(), 0);
  EXPECT_EQ(keep.back(), n - 1);
  EXPECT_TRUE(std::binary_search(keep.begin(), keep.end(), 123457));
  EXPECT_TRUE(std::binary_search(keep.begin(), keep.end(), 4242));
  // Every bucket's extremes survive: the kept samples' range equals the full range.
  double lo = INFINITY, hi = -INFINITY;
  for (Eigen::Index i : keep) {
    lo = std::min(lo, y[i]);
    hi = std::max(hi, y[i]);
  }
  EXPECT_EQ(lo, y.minCoeff());
  EXPECT_EQ(hi, y.maxCoeff());
}

TEST(SelectPlotSamples, HysteresisKeepsExtremesOfBothAxes) {
  const Eigen::Index n = 100000;
  const Eigen::VectorXd s = Eigen::VectorXd::LinSpaced(n, 0, 40 * M_PI);
  const Eigen::VectorXd x = s.array().sin();
  const Eigen::VectorXd f = (s.array() + 0.3).sin();
  const auto keep = SelectPlotSamples(x, f, 1000);
  EXPECT_LE(keep.size(), 1000u);
  double xmax = -INFINITY, fmax = -INFINITY;
  for (Eigen::Index i : keep) {
    xmax = std::max(xmax, x[i]);
    fmax = std::max(fmax, f[i]);
  }
  EXPECT_EQ(xmax, x.maxCoeff());
  EXPECT_EQ(fmax, f.maxCoeff());
}

TEST(SelectPlotSamples, RejectsMismatchedInput) {
  EXPECT_THROW(SelectPlotSamples(Eigen::VectorXd(3), Eigen::VectorXd(4)), std::invalid_argument);
}

}  // namespace
}  // namespace hybridtest::report
