#include "hybridtest/transfer/actuator.h"

#include <Eigen/Dense>

#include <cmath>
#include <complex>
#include <numbers>

namespace hybridtest::transfer {

Actuator::Actuator(const EmulatedBenchConfig& config)
    : lag_(config.lag),
      step_(config.internal_step),
      max_reference_move_(config.velocity_limit * config.internal_step),
      first_order_gain_(config.lag.type == ServoLag::Type::kFirstOrder
                            ? 1.0 - std::exp(-config.internal_step / config.lag.time_constant)
                            : 1.0),
      reference_(config.initial_position),
      delayed_reference_(config.initial_position),
      delay_line_(static_cast<std::size_t>(std::lround(config.delay / config.internal_step)),
                  config.initial_position),
      position_(config.initial_position) {
  if (config.approach != Approach::kMonotone || lag_.type != ServoLag::Type::kSecondOrder) return;
  // The discretised lag (semi-implicit Euler on (p, v)) has the poles z of
  // z² − T z + det = 0 with det = 1 − 2ζωh and T = 2 − ω²h² − 2ζωh.
  const double omega = 2.0 * std::numbers::pi * lag_.natural_frequency;
  const double wh = omega * step_;
  const double det = 1.0 - 2.0 * lag_.damping_ratio * wh;
  const double trace = 2.0 - wh * wh - 2.0 * lag_.damping_ratio * wh;
  if (!(det > 0.0)) return;
  const double cos_theta = trace / (2.0 * std::sqrt(det));
  if (!(std::abs(cos_theta) < 1.0)) return;  // real poles: no overshoot to shape away
  const double theta = std::acos(cos_theta);
  const double half_period = std::numbers::pi / theta;  // [steps]
  const auto whole = static_cast<std::size_t>(std::floor(half_period));
  // Taps at 0, N and N + 1 steps (N = the whole steps of the half period) with unit sum whose
  // zeros cancel the lag's poles exactly: a1 + a2 w^N + a3 w^(N+1) = 0, w = 1/z.
  const std::complex<double> w = std::polar(1.0 / std::sqrt(det), -theta);
  const std::complex<double> u = std::pow(w, static_cast<double>(whole));
  const std::complex<double> v = u * w;
  Eigen::Matrix3d a;
  a << 1.0, u.real(), v.real(), 0.0, u.imag(), v.imag(), 1.0, 1.0, 1.0;
  const Eigen::Vector3d taps = a.colPivHouseholderQr().solve(Eigen::Vector3d(0.0, 0.0, 1.0));
  if (!taps.allFinite() || (taps.array() < 0.0).any()) return;
  shaped_ = true;
  shaper_a1_ = taps(0);
  shaper_a2_ = taps(1);
  shaper_a3_ = taps(2);
  shaper_line_.assign(whole + 2, config.initial_position);
}

void Actuator::Step(double target) {
  // Rate-limited reference; lands exactly on the target.
  const double gap = target - reference_;
  reference_ = std::abs(gap) <= max_reference_move_
                   ? target
                   : reference_ + std::copysign(max_reference_move_, gap);
  // Pure delay.
  if (delay_line_.empty()) {
    delayed_reference_ = reference_;
  } else {
    delay_line_.push_back(reference_);
    delayed_reference_ = delay_line_.front();
    delay_line_.pop_front();
  }
  // Input shaping (newest at the back: the back − n is r_d(t − n steps)).
  double servo_reference = delayed_reference_;
  if (shaped_) {
    shaper_line_.push_back(delayed_reference_);
    shaper_line_.pop_front();
    servo_reference = shaper_a1_ * delayed_reference_ + shaper_a2_ * shaper_line_[1] +
                      shaper_a3_ * shaper_line_[0];
  }
  // Servo lag.
  switch (lag_.type) {
    case ServoLag::Type::kNone:
      velocity_ = (servo_reference - position_) / step_;
      position_ = servo_reference;
      break;
    case ServoLag::Type::kFirstOrder: {
      const double previous = position_;
      position_ += first_order_gain_ * (servo_reference - position_);
      velocity_ = (position_ - previous) / step_;
      break;
    }
    case ServoLag::Type::kSecondOrder: {
      const double omega = 2.0 * std::numbers::pi * lag_.natural_frequency;
      const double acceleration = omega * omega * (servo_reference - position_) -
                                  2.0 * lag_.damping_ratio * omega * velocity_;
      velocity_ += step_ * acceleration;
      position_ += step_ * velocity_;
      break;
    }
  }
}

bool Actuator::reference_arrived(double target) const {
  if (reference_ != target || delayed_reference_ != target) return false;
  for (double r : delay_line_) {
    if (r != target) return false;
  }
  for (double r : shaper_line_) {
    if (r != target) return false;
  }
  return true;
}

}  // namespace hybridtest::transfer
