// See tracking_criteria.h.
#include "hybridtest/runner/tracking_criteria.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hybridtest::runner {

void TrackingCriteria::Reserve(long capacity, double tick, double max_lag) {
  xc_.assign(static_cast<std::size_t>(std::max(0L, capacity)), 0.0);
  xm_.assign(xc_.size(), 0.0);
  tick_ = tick;
  max_lag_ = max_lag;
  n_ = 0;
  sc_ = scc_ = se_ = see_ = emax_ = cmax_ = 0.0;
}

void TrackingCriteria::Add(double command, double measured) {
  if (static_cast<std::size_t>(n_) < xc_.size()) {
    xc_[static_cast<std::size_t>(n_)] = command;
    xm_[static_cast<std::size_t>(n_)] = measured;
  }
  ++n_;
  const double e = measured - command;
  sc_ += command;
  scc_ += command * command;
  se_ += e;
  see_ += e * e;
  emax_ = std::max(emax_, std::abs(e));
  cmax_ = std::max(cmax_, std::abs(command));
}

namespace {
double Std(double s, double ss, long n) {
  const double mean = s / static_cast<double>(n);
  return std::sqrt(std::max(0.0, ss / static_cast<double>(n) - mean * mean));
}
}  // namespace

double TrackingCriteria::J2() const {
  if (n_ < 2) return std::numeric_limits<double>::quiet_NaN();
  const double sc = Std(sc_, scc_, n_);
  return sc > 0.0 ? 100.0 * Std(se_, see_, n_) / sc : std::numeric_limits<double>::quiet_NaN();
}

double TrackingCriteria::J3() const {
  return cmax_ > 0.0 ? 100.0 * emax_ / cmax_ : std::numeric_limits<double>::quiet_NaN();
}

double TrackingCriteria::J1_ms() const {
  const long n = std::min<long>(n_, static_cast<long>(xc_.size()));
  if (n < 4 || !(tick_ > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  const long max_lag =
      std::max(0L, std::min(n - 4, static_cast<long>(std::ceil(max_lag_ / tick_)) + 1));
  // R(L): the correlation coefficient of x_c(i) and x_m(i + L) over their overlap (x_m lags
  // x_c by L ticks); normalised per lag, so a growing or decaying response does not bias it.
  auto corr = [&](long lag) {
    const long len = n - lag;
    double sc = 0.0, sm = 0.0;
    for (long i = 0; i < len; ++i) {
      sc += xc_[static_cast<std::size_t>(i)];
      sm += xm_[static_cast<std::size_t>(i + lag)];
    }
    const double mc = sc / static_cast<double>(len), mm = sm / static_cast<double>(len);
    double scm = 0.0, scc = 0.0, smm = 0.0;
    for (long i = 0; i < len; ++i) {
      const double a = xc_[static_cast<std::size_t>(i)] - mc;
      const double b = xm_[static_cast<std::size_t>(i + lag)] - mm;
      scm += a * b;
      scc += a * a;
      smm += b * b;
    }
    return scc > 0.0 && smm > 0.0 ? scm / std::sqrt(scc * smm) : 0.0;
  };
  long best = 0;
  double best_r = corr(0);
  std::vector<double> r;
  r.reserve(static_cast<std::size_t>(max_lag) + 1);
  r.push_back(best_r);
  for (long lag = 1; lag <= max_lag; ++lag) {
    r.push_back(corr(lag));
    if (r[static_cast<std::size_t>(lag)] > best_r) {
      best_r = r[static_cast<std::size_t>(lag)];
      best = lag;
    }
  }
  // Sub-tick: the vertex of the parabola through the peak and its neighbours.
  double frac = 0.0;
  if (best > 0 && best < max_lag) {
    const double a = r[static_cast<std::size_t>(best - 1)], b = r[static_cast<std::size_t>(best)],
                 c = r[static_cast<std::size_t>(best + 1)];
    const double den = a - 2.0 * b + c;
    if (den < 0.0) frac = 0.5 * (a - c) / den;
  }
  return 1e3 * tick_ * (static_cast<double>(best) + frac);
}

nlohmann::json TrackingCriteria::ToJson() const {
  auto num = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
  return {{"J1_ms", num(J1_ms())}, {"J2", num(J2())}, {"J3", num(J3())}, {"samples", n_}};
}

}  // namespace hybridtest::runner
