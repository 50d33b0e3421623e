// See tracking.h.
#include "hybridtest/common/tracking.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace hybridtest {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The correlation coefficient of y(i) and x(i + lag) over their overlap; normalised per lag,
// so a growing or decaying response does not bias it.
double Correlation(std::span<const double> x, std::span<const double> y, std::size_t n,
                   std::size_t lag) {
  const std::size_t len = n - lag;
  double sy = 0.0, sx = 0.0;
  for (std::size_t i = 0; i < len; ++i) {
    sy += y[i];
    sx += x[i + lag];
  }
  const double my = sy / static_cast<double>(len), mx = sx / static_cast<double>(len);
  double syx = 0.0, syy = 0.0, sxx = 0.0;
  for (std::size_t i = 0; i < len; ++i) {
    const double a = y[i] - my;
    const double b = x[i + lag] - mx;
    syx += a * b;
    syy += a * a;
    sxx += b * b;
  }
  return syy > 0.0 && sxx > 0.0 ? syx / std::sqrt(syy * sxx) : 0.0;
}

double StandardDeviation(std::span<const double> v, std::span<const double> minus) {
  double s = 0.0;
  for (std::size_t i = 0; i < v.size(); ++i) s += v[i] - (minus.empty() ? 0.0 : minus[i]);
  const double mean = s / static_cast<double>(v.size());
  double ss = 0.0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const double d = v[i] - (minus.empty() ? 0.0 : minus[i]) - mean;
    ss += d * d;
  }
  return std::sqrt(ss / static_cast<double>(v.size()));
}

}  // namespace

double TrackingDelayMs(std::span<const double> x, std::span<const double> y, double tick,
                       double max_lag) {
  const std::size_t n = std::min(x.size(), y.size());
  if (n < 4 || !(tick > 0.0)) return kNaN;
  const auto lags = static_cast<std::size_t>(std::max(0.0, std::ceil(max_lag / tick))) + 1;
  const std::size_t max = std::min(n - 4, lags);
  std::size_t best = 0;
  std::vector<double> r;
  r.reserve(max + 1);
  r.push_back(Correlation(x, y, n, 0));
  for (std::size_t lag = 1; lag <= max; ++lag) {
    r.push_back(Correlation(x, y, n, lag));
    if (r[lag] > r[best]) best = lag;
  }
  // Sub-tick: the vertex of the parabola through the peak and its neighbours.
  double frac = 0.0;
  if (best > 0 && best < max) {
    const double a = r[best - 1], b = r[best], c = r[best + 1];
    const double den = a - 2.0 * b + c;
    if (den < 0.0) frac = 0.5 * (a - c) / den;
  }
  return 1e3 * tick * (static_cast<double>(best) + frac);
}

double NormalisedRmsError(std::span<const double> x, std::span<const double> y) {
  const std::size_t n = std::min(x.size(), y.size());
  if (n < 2) return kNaN;
  const double sy = StandardDeviation(y.first(n), {});
  return sy > 0.0 ? 100.0 * StandardDeviation(x.first(n), y.first(n)) / sy : kNaN;
}

double PeakError(std::span<const double> x, std::span<const double> y) {
  const std::size_t n = std::min(x.size(), y.size());
  double emax = 0.0, ymax = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    emax = std::max(emax, std::abs(x[i] - y[i]));
    ymax = std::max(ymax, std::abs(y[i]));
  }
  return ymax > 0.0 ? 100.0 * emax / ymax : kNaN;
}

}  // namespace hybridtest
