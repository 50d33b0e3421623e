// See tracking_criteria.h.
#include "hybridtest/runner/tracking_criteria.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "hybridtest/common/tracking.h"

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

double TrackingCriteria::J1_ms() const { return J1_ms(n_); }

double TrackingCriteria::J1_ms(long window) const {
  const auto n = static_cast<std::size_t>(std::min<long>(n_, static_cast<long>(xc_.size())));
  const auto w = std::min(n, static_cast<std::size_t>(std::max(0L, window)));
  return TrackingDelayMs(std::span<const double>(xm_.data() + (n - w), w),
                         std::span<const double>(xc_.data() + (n - w), w), tick_, max_lag_);
}

nlohmann::json TrackingCriteria::ToJson() const {
  auto num = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
  return {{"J1_ms", num(J1_ms())}, {"J2", num(J2())}, {"J3", num(J3())}, {"samples", n_}};
}

}  // namespace hybridtest::runner
