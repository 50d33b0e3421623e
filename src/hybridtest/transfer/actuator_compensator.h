#pragma once
// ActuatorCompensator: the delay compensation of ONE actuator (the methods, polynomial and ATS,
// are specified in delay_compensator.h): its own history of targets, its own ATS window and
// its own estimate [a0, a1, a2]. A DelayCompensator holds one per actuator of the transfer
// system it wraps, so each actuator of a specimen on n actuators is compensated for its own
// delay. Positions here are relative to the actuator's settled command. The stepping path
// allocates nothing (rings sized in Start).
#include <array>
#include <cstddef>
#include <vector>

#include <nlohmann/json.hpp>

namespace hybridtest::transfer {

enum class CompensationMethod { kPolynomial, kAts };

struct CompensatorConfig {
  CompensationMethod method = CompensationMethod::kAts;
  double delay = 0.02;    // τ [s]: the extrapolation (polynomial), the initial a1 (ats)
  int order = 2;          // polynomial order p (1..4)
  int spacing = 0;        // polynomial: ticks between the nodes, 0: round(τ/(p h)) ≥ 1
  double window = 1.0;    // ats: least-squares window [s]
  int update_every = 16;  // ats: ticks between updates
  double threshold = 2.54e-4;  // ats: smallest max |x_m| in the window that updates [m]
  std::array<double, 3> lower{0.7, 0.0, 0.0};        // bounds of a0, a1 [s], a2 [s²]
  std::array<double, 3> upper{1.3, 0.08, 0.0032};
  std::array<double, 3> rate_limit{2.0, 0.05, 0.001};  // per second: [1/s], [-], [s]
};

class ActuatorCompensator {
 public:
  // `config` validated by the caller (ValidateCompensatorConfig, delay_compensator.h).
  explicit ActuatorCompensator(const CompensatorConfig& config);

  // Sizes the rings for a paced run with step `tick` [s]; the history starts at rest.
  void Start(double tick);
  // The command to send for target x [m] (relative); one call per tick.
  double Compensate(double x);
  // The command sent this tick and the position measured [m] (relative): the ATS window,
  // identified every `update_every` ticks.
  void Record(double sent, double measured);

  // a0, a1 [s], a2 [s²] (ats; polynomial: 1, τ, 0).
  const std::array<double, 3>& coefficients() const { return a_; }
  double estimated_delay() const { return a_[0] > 0.0 ? a_[1] / a_[0] : 0.0; }
  long updates() const { return updates_; }
  // The estimates and their extremes.
  nlohmann::json ToJson() const;

 private:
  void Identify();

  CompensatorConfig config_;
  double tick_ = 0.0;
  std::vector<double> poly_;         // L_i(ξ), i = 0..p
  int spacing_ = 1;                  // Δ [ticks]
  std::vector<double> history_;      // the last p Δ + 1 targets (a ring)
  std::size_t history_head_ = 0;
  std::array<double, 3> targets_{};  // the last three targets, newest first
  long ticks_ = 0;
  std::array<double, 3> a_{1.0, 0.0, 0.0};
  // ATS window: commands sent and measured positions (relative), a ring.
  std::vector<double> sent_, measured_;
  std::size_t head_ = 0, size_ = 0;
  double last_update_tick_ = 0.0;
  long updates_ = 0;
  std::array<double, 3> min_a_{}, max_a_{};
};

}  // namespace hybridtest::transfer
