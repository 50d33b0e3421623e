#pragma once
// Actuator: the emulated servo-controlled actuator of EmulatedBench, advanced one internal
// step at a time. All SI.
//
//   reference  r(t): ramps toward the target at most velocity_limit·dt per step;
//   delayed    r_d(t) = r(t − delay), delay rounded to whole internal steps;
//   shaped     approach: monotone with an underdamped second-order lag: a zero-vibration
//              input shaper (Singer & Seering 1990). In continuous time
//              r_s(t) = A1 r_d(t) + A2 r_d(t − τ), τ the lag's damped half period, K its
//              amplitude decay over τ, A1 = 1/(1+K), A2 = K/(1+K): the shaped lag's impulse
//              response is ≥ 0 and zero after τ, so a reference that moves one way (a ramp)
//              gives a position that moves the same way only — no overshoot, no load
//              reversal. Here, for the discretised lag with poles z: taps at 0, N and N + 1
//              internal steps (N the whole steps of τ), weights of unit sum whose zeros
//              cancel the poles exactly: a1 + a2 z^−N + a3 z^−(N+1) = 0.
//              Otherwise r_s = r_d (a first-order lag or none never overshoots).
//   position   p(t) follows r_s through the servo lag:
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

  // True once the reference, the delayed and the shaped reference have reached `target` [m].
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
  // The input shaper (approach: monotone, underdamped second-order lag only).
  bool shaped_ = false;
  double shaper_a1_ = 1.0, shaper_a2_ = 0.0, shaper_a3_ = 0.0;  // tap weights
  std::deque<double> shaper_line_;  // the last N + 2 delayed references, oldest first
  double position_;
  double velocity_ = 0.0;
};

}  // namespace hybridtest::transfer
