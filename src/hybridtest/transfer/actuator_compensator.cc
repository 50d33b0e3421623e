// See actuator_compensator.h.
#include "hybridtest/transfer/actuator_compensator.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdlib>


namespace hybridtest::transfer {

ActuatorCompensator::ActuatorCompensator(const CompensatorConfig& config) : config_(config) {
  a_ = {1.0, config_.delay, 0.5 * config_.delay * config_.delay};
  if (config_.method == CompensationMethod::kAts) {
    for (int i = 0; i < 3; ++i) a_[i] = std::clamp(a_[i], config_.lower[i], config_.upper[i]);
  } else {
    a_[2] = 0.0;
  }
  min_a_ = max_a_ = a_;
}

void ActuatorCompensator::Start(double tick) {
  tick_ = tick;
  ticks_ = 0;
  targets_.fill(0.0);
  // Lagrange weights at ξ = τ/(Δh) on the nodes 0, −1, …, −p (in units of Δ ticks).
  spacing_ = config_.spacing > 0
                 ? config_.spacing
                 : std::max(1, static_cast<int>(std::lround(config_.delay / (config_.order * tick))));
  const double xi = config_.delay / (spacing_ * tick);
  history_.assign(static_cast<std::size_t>(config_.order * spacing_ + 1), 0.0);
  history_head_ = 0;
  poly_.assign(static_cast<std::size_t>(config_.order) + 1, 1.0);
  for (int i = 0; i <= config_.order; ++i) {
    for (int j = 0; j <= config_.order; ++j) {
      if (j != i) poly_[static_cast<std::size_t>(i)] *= (xi + j) / static_cast<double>(j - i);
    }
  }
  const auto n = static_cast<std::size_t>(std::max(4.0, std::ceil(config_.window / tick)));
  sent_.assign(n, 0.0);
  measured_.assign(n, 0.0);
  head_ = size_ = 0;
  last_update_tick_ = 0.0;
}

double ActuatorCompensator::Compensate(double x) {
  for (std::size_t i = targets_.size() - 1; i > 0; --i) targets_[i] = targets_[i - 1];
  targets_[0] = x;
  if (config_.method == CompensationMethod::kPolynomial) {
    const std::size_t n = history_.size();
    history_head_ = (history_head_ + 1) % n;
    history_[history_head_] = x;
    if (ticks_ < config_.order * spacing_) return x;  // not enough history yet
    double c = 0.0;
    for (std::size_t i = 0; i < poly_.size(); ++i) {
      c += poly_[i] * history_[(history_head_ + n - i * static_cast<std::size_t>(spacing_)) % n];
    }
    return c;
  }
  if (ticks_ < 2) return a_[0] * x;
  const double v = (targets_[0] - targets_[1]) / tick_;
  const double a = (targets_[0] - 2.0 * targets_[1] + targets_[2]) / (tick_ * tick_);
  return a_[0] * x + a_[1] * v + a_[2] * a;
}

void ActuatorCompensator::Identify() {
  const std::size_t n = sent_.size();
  if (size_ < 8) return;
  // Oldest first: sample i of the window is ring index (head − size + i).
  auto at = [&](const std::vector<double>& ring, std::size_t i) {
    return ring[(head_ + n - size_ + i) % n];
  };
  double peak = 0.0;
  Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
  Eigen::Vector3d aty = Eigen::Vector3d::Zero();
  for (std::size_t i = 2; i < size_; ++i) {
    const double x = at(measured_, i), x1 = at(measured_, i - 1), x2 = at(measured_, i - 2);
    const Eigen::Vector3d row(x, (x - x1) / tick_, (x - 2.0 * x1 + x2) / (tick_ * tick_));
    ata += row * row.transpose();
    aty += row * at(sent_, i);
    peak = std::max(peak, std::abs(x));
  }
  if (peak < config_.threshold) return;
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(ata);
  if (ldlt.info() != Eigen::Success) return;
  const Eigen::Vector3d fit = ldlt.solve(aty);
  if (!fit.allFinite()) return;
  const double elapsed = (static_cast<double>(ticks_) - last_update_tick_) * tick_;
  for (int i = 0; i < 3; ++i) {
    const double step = config_.rate_limit[static_cast<std::size_t>(i)] * elapsed;
    const double target = std::clamp(fit(i), config_.lower[static_cast<std::size_t>(i)],
                                      config_.upper[static_cast<std::size_t>(i)]);
    auto& a = a_[static_cast<std::size_t>(i)];
    a = std::clamp(target, a - step, a + step);
    min_a_[static_cast<std::size_t>(i)] = std::min(min_a_[static_cast<std::size_t>(i)], a);
    max_a_[static_cast<std::size_t>(i)] = std::max(max_a_[static_cast<std::size_t>(i)], a);
  }
  last_update_tick_ = static_cast<double>(ticks_);
  ++updates_;
}

void ActuatorCompensator::Record(double sent, double measured) {
  ++ticks_;
  if (config_.method != CompensationMethod::kAts) return;
  sent_[head_] = sent;
  measured_[head_] = measured;
  head_ = (head_ + 1) % sent_.size();
  if (size_ < sent_.size()) ++size_;
  if (ticks_ % config_.update_every == 0) Identify();
}

nlohmann::json ActuatorCompensator::ToJson() const {
  return {{"method", config_.method == CompensationMethod::kAts ? "ats" : "polynomial"},
          {"spacing_ticks", spacing_},
          {"a0", a_[0]}, {"a1_s", a_[1]}, {"a2_s2", a_[2]},
          {"estimated_delay_s", estimated_delay()},
          {"updates", updates_},
          {"a_min", min_a_}, {"a_max", max_a_}};
}

}  // namespace hybridtest::transfer
