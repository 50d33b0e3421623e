#pragma once
// The delay-dependent stability check of a real-time run, before anything moves
// (docs/real-time.md). A transfer that lags its command by τ turns the specimen's K0 into
// K0·e^{−sτ}: for a spring, a negative damping K0·τ (Horiuchi et al. 1999). Per physical slot s,
// with the model linearised at x_0 (q̇ = u; the extra states z are left out):
//
//   q̈ = F_q q + F_u q̇ + Σ_j b_j r_j,   r_j = k_j d_jᵀ q   (b_j = ∂u̇/∂r_j, d_j = ∂d_j/∂q,
//                                                         k_j every slot's K0)
//   P(s) = s² I − s F_u − F_q − Σ_{j≠s} b_j k_j d_jᵀ,     g(s) = d_sᵀ P(s)⁻¹ b_s
//
// and with slot s delayed the characteristic equation is 1 = k_s e^{−sτ} g(s). A specimen on
// several actuators serving the slots B delays them all together (every actuator lags): with
// P(s) built from the slots outside B and L(s) = K_B· D P(s)⁻¹ b_B (|B| × |B|), the equation
// is det(I − e^{−sτ} L(s)) = 0, crossing the imaginary axis where an eigenvalue λ of L(jω) has
// |λ| = 1, for τ = (arg λ mod 2π) / ω; τ_c is the smallest, shared by the slots of B. A root crosses
// the imaginary axis at the frequencies ω where |k_s g(jω)| = 1, for the delays
// τ = (arg(k_s g(jω)) mod 2π) / ω; the CRITICAL DELAY τ_c is the smallest of them (+∞ when
// |k_s g| never reaches 1: stable for any delay). For one mass, m ẍ + c ẋ + k_N x + k_E x(t−τ)
// = 0, this is τ_c = atan2(cω, mω² − k_N)/ω at (mω² − k_N)² + (cω)² = k_E², ≈ c/k_E.
//
// The plant's delay is its phase delay −arg G(jω_c)/ω_c at the crossing frequency (rt_plant:
// the pure delay, the lag, or the servo-hydraulic transfer function, plus half a tick of
// hold for the continuous plants); a compensator removes its configured delay (polynomial) or
// its initial estimate a1/a0 (ATS). A slot whose remaining delay exceeds τ_c makes the run
// unstable (the check assumes the run is stable without delay; it treats the sampled loop as
// continuous, which overestimates τ_c: Lu et al. 2022).
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "hybridtest/runner/session.h"

namespace hybridtest::runner {

struct SlotDelayMargin {
  std::string slot;
  std::string substructure;        // the substructure serving it (the slot map's name)
  double k0 = 0.0;                 // [N/m]
  double critical_delay = std::numeric_limits<double>::infinity();  // τ_c [s]
  double crossing_hz = 0.0;        // ω_c / 2π [Hz]
  double plant_delay = 0.0;        // the transfer's phase delay at ω_c [s]
  double compensation = 0.0;       // the delay its compensator removes [s]
  double remaining_delay = 0.0;    // max(0, plant_delay − compensation) [s]
  bool known_plant = false;        // the transfer is an rt_plant (its delay is known)
  // The slots delayed together to find τ_c: 1, or every slot of a specimen on several
  // actuators (its coupled loop: every actuator lags by the same τ).
  int delayed_together = 1;
  bool unstable() const { return remaining_delay > critical_delay; }
};

// The margins of every physical slot of `session` (built, not initialised), in the model's slot
// order, found through the session's slot map: a substructure of several slots gives one
// margin per slot, with its K0 matrix coupling the slots (slot s delayed: r_s = K_s· d(t − τ),
// the others undelayed) and the largest phase delay of its actuators
// (TransferSystem::PhaseDelay). Throws ModelError where the model cannot be linearised.
std::vector<SlotDelayMargin> CheckDelayStability(const Session& session);

// Throws ConfigError (before any command) naming the slot, its critical delay and the plant's
// delay when a margin is exceeded and the spec's real_time.force is not set.
void RefuseUnstable(const Session& session, const std::vector<SlotDelayMargin>& margins);

nlohmann::json ToJson(const std::vector<SlotDelayMargin>& margins);
std::string Describe(const SlotDelayMargin& margin);

}  // namespace hybridtest::runner
