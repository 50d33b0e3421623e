#include "hybridtest/report/plot_decimate.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hybridtest::report {
namespace {
// Index of the smallest and the largest finite value of v in [begin, end); -1 when none.
void AddExtremes(const Eigen::VectorXd& v, Eigen::Index begin, Eigen::Index end,
                 std::vector<Eigen::Index>& out) {
  Eigen::Index lo = -1, hi = -1;
  for (Eigen::Index i = begin; i < end; ++i) {
    if (!std::isfinite(v[i])) continue;
    if (lo < 0 || v[i] < v[lo]) lo = i;
    if (hi < 0 || v[i] > v[hi]) hi = i;
  }
  if (lo >= 0) out.push_back(lo);
  if (hi >= 0) out.push_back(hi);
}
}  // namespace

std::vector<Eigen::Index> SelectPlotSamples(const Eigen::VectorXd& x, const Eigen::VectorXd& y,
                                            Eigen::Index max_points) {
  if (x.size() != y.size()) {
    throw std::invalid_argument("SelectPlotSamples: x and y differ in length");
  }
  if (max_points < 8) throw std::invalid_argument("SelectPlotSamples: max_points < 8");
  const Eigen::Index n = y.size();
  std::vector<Eigen::Index> keep;
  if (n <= max_points) {
    keep.resize(static_cast<std::size_t>(n));
    for (Eigen::Index i = 0; i < n; ++i) keep[static_cast<std::size_t>(i)] = i;
    return keep;
  }
  // Buckets of n / buckets samples (the remainder spread over the first buckets).
  const Eigen::Index buckets = (max_points - 2) / 4;
  keep.reserve(static_cast<std::size_t>(4 * buckets + 2));
  keep.push_back(0);
  for (Eigen::Index b = 0; b < buckets; ++b) {
    const Eigen::Index begin = b * n / buckets;
    const Eigen::Index end = (b + 1) * n / buckets;
    AddExtremes(y, begin, end, keep);
    AddExtremes(x, begin, end, keep);
  }
  keep.push_back(n - 1);
  // Back into time order, without repeats.
  std::sort(keep.begin(), keep.end());
  keep.erase(std::unique(keep.begin(), keep.end()), keep.end());
  return keep;
}

}  // namespace hybridtest::report
