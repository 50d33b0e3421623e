#include "hybridtest/transfer/actuator.h"

#include <cmath>
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
      position_(config.initial_position) {}

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
  // Servo lag.
  switch (lag_.type) {
    case ServoLag::Type::kNone:
      velocity_ = (delayed_reference_ - position_) / step_;
      position_ = delayed_reference_;
      break;
    case ServoLag::Type::kFirstOrder: {
      const double previous = position_;
      position_ += first_order_gain_ * (delayed_reference_ - position_);
      velocity_ = (position_ - previous) / step_;
      break;
    }
    case ServoLag::Type::kSecondOrder: {
      const double omega = 2.0 * std::numbers::pi * lag_.natural_frequency;
      const double acceleration = omega * omega * (delayed_reference_ - position_) -
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
  return true;
}

}  // namespace hybridtest::transfer
