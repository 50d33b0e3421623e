#pragma once
// Actuator: the emulated servo-controlled actuator of EmulatedBench, advanced one internal
// step at a time. All SI.
//
//   reference  r(t): ramps toward the target at most velocity_limit·dt per step;
//   delayed    r_d(t) = r(t − delay), delay rounded to whole internal steps;
//   position   p(t) follows r_d through the servo lag:
//                none:          p = r_d
//                first order:   τ ṗ = r_d − p           (exact discretisation)
//                second order:  p̈ = ωn² (r_d − p) − 2 ζ ωn ṗ  (semi-implicit Euler)
#include <nlohmann/json.hpp>

#include <deque>

#include "hybridtest/transfer/bench_config.h"

namespace hybridtest::transfer {

class Actuator {
 public:
  // Uses velocity_limit, lag, delay, internal_step and initial_position of `config`.
  explicit Actuator(const EmulatedBenchConfig& config);

  // Advances one internal step toward `target`. Unit: [m].
  void Step(double target);

  // True once the reference and the delayed reference have both reached `target` [m].
  bool reference_arrived(double target) const;

  double position() const { return position_; }  // Unit: [m].
  double velocity() const { return velocity_; }  // Unit: [m/s].
  double step() const { return step_; }          // internal step. Unit: [s].
  // Reference, delayed reference, delay line, position and velocity (SI), for a checkpoint;
  // RestoreState(SaveState()) continues bit-identically. Throws hybridtest::Error.
  nlohmann::json SaveState() const;
  void RestoreState(const nlohmann::json& state);

 private:
  ServoLag lag_;
  double step_;
  double max_reference_move_;   // velocity_limit · step. Unit: [m].
  double first_order_gain_;     // 1 − exp(−step/τ)
  double reference_;
  double delayed_reference_;
  std::deque<double> delay_line_;  // references waiting out the delay, oldest first
  double position_;
  double velocity_ = 0.0;
};

}  // namespace hybridtest::transfer
