#pragma once
// DelayCompensator: a TransferSystem decorator that rewrites each target command x_t of a
// paced (real-time) run so that the wrapped actuator's measured position x_m follows x_t
// despite its delay and amplitude error (transfer type `compensated`, io/rt_plant_reader.h).
// Unpaced (settled moves) it forwards the command unchanged. Two methods:
//
//   polynomial  Horiuchi, Inoue, Konno & Namita (1999, "Real-time hybrid experimental system
//               with actuator delay compensation and its application to a piping system with
//               energy absorber", Earthquake Eng. Struct. Dyn. 28): the target is extrapolated
//               τ ahead by the Lagrange polynomial of order p through p + 1 past targets Δ
//               ticks apart:  x_c,k = Σ_{i=0..p} L_i(ξ) x_t,k−iΔ,  ξ = τ/(Δh),
//               L_i(ξ) = Π_{j≠i} (ξ + j)/(j − i).  τ is fixed (`delay`); Δ (`spacing`, default
//               round(τ/(p h)) ≥ 1) keeps ξ near p: nodes one tick apart extrapolated over many
//               ticks would amplify the tick-to-tick noise by the weights' size.
//   ats         the adaptive time series of Chae, Kazemibidokhti & Ricles (2013, "Adaptive time
//               series compensator for delay compensation of servo-hydraulic actuator systems
//               for real-time hybrid simulation", Earthquake Eng. Struct. Dyn. 42):
//                  x_c = a0 x_t + a1 ẋ_t + a2 ẍ_t
//               (derivatives by backward differences over one tick) with [a0 a1 a2] identified
//               every `update_every` ticks by least squares over a moving window of `window`
//               seconds from the inverse relation  x_c ≈ a0 x_m + a1 ẋ_m + a2 ẍ_m  (the commands
//               actually sent against the measured response), once the window's largest |x_m|
//               exceeds `threshold`; each coefficient is then clamped to its bounds and its
//               change limited to rate_limit · (time since the last update). a1/a0 is the
//               estimated delay [s], a0 the amplitude correction. Initially a0 = 1,
//               a1 = `delay`, a2 = a1²/2.
//
// Every actuator of the wrapped transfer system is compensated on its own (one
// ActuatorCompensator each, actuator_compensator.h: its own history, window and estimate), so a
// specimen on n actuators with different delays is served by one `compensated` transfer.
// Positions are relative to each actuator's first command (the settled one), so a p0 ≠ 0 is
// not scaled by a0. The measurement returned is the wrapped one; the exchange keeps the TARGET as its
// command (what the safety gate checked), so J1–J3 measure the tracking of the target. The
// stepping path allocates nothing (rings preallocated in StartPaced).
#include <array>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "hybridtest/transfer/actuator_compensator.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer {

// Throws ConfigError naming the field.
void ValidateCompensatorConfig(const CompensatorConfig& config, const std::string& where);

class DelayCompensator final : public TransferSystem {
 public:
  // One compensator per actuator of `inner`, each starting from `config`.
  DelayCompensator(std::unique_ptr<TransferSystem> inner, CompensatorConfig config);

  void Activate() override { inner_->Activate(); }
  int num_actuators() const override { return inner_->num_actuators(); }
  void Execute(std::span<const double> commands, std::span<Measurement> out) override;
  void Hold() noexcept override { inner_->Hold(); }
  void Deactivate() override { inner_->Deactivate(); }
  BenchUnits bench_units() const override { return inner_->bench_units(); }
  std::string Describe() const override;
  std::optional<std::vector<Measurement>> ReadAll() override { return inner_->ReadAll(); }
  BenchAnnouncement Announce() const override { return inner_->Announce(); }
  std::optional<long> commands_received() const override { return inner_->commands_received(); }
  void StartPaced(double tick, const Clock& clock) override;
  bool can_run_paced() const override { return inner_->can_run_paced(); }
  TransferSystem* served_plant() override { return inner_->served_plant(); }
  std::optional<double> PhaseDelay(double omega, double tick) const override {
    return inner_->PhaseDelay(omega, tick);
  }
  // The smallest estimate over the actuators (against the largest plant delay, PhaseDelay:
  // the delay check stays on the safe side). [s]
  double compensated_delay() const override;
  double actuator_compensated_delay(int k) const override { return actuator(k).estimated_delay(); }
  nlohmann::json CompensationRecord() const override { return ToJson(); }

  // Actuator k's compensator (0 ≤ k < num_actuators()).
  const ActuatorCompensator& actuator(int k) const {
    return channels_.at(static_cast<std::size_t>(k));
  }
  // The estimates and their extremes, for the run's statistics: one actuator's record, or
  // {"method", "actuators": [one record per actuator]} for several.
  nlohmann::json ToJson() const;
  const TransferSystem& inner() const { return *inner_; }
  TransferSystem& inner() { return *inner_; }

 private:
  std::unique_ptr<TransferSystem> inner_;
  CompensatorConfig config_;
  bool paced_ = false;
  std::vector<ActuatorCompensator> channels_;  // one per actuator
  std::vector<double> origin_;                 // each actuator's settled command [m]
  std::vector<double> sent_;                   // this tick's absolute commands [m]
};

}  // namespace hybridtest::transfer
