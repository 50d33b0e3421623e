#pragma once
// RtPlant: an emulated actuator and specimen for real-time hybrid testing (transfer type
// `rt_plant`). In a paced run (StartPaced) every Execute advances the plant to clock.Now()
// holding the previous command (zero-order hold), then records the new command and returns
// the measurement at Now(); without StartPaced every Execute is a settled move (a
// pseudo-dynamic test): position = the plant's static response, force = the static force.
// Speaks SI (m, N). Positions are absolute; the plant's state is the displacement x from p0.
//
// Specimen (the load cell's force, x from p0, v = ẋ, a = ẍ):
//     f = m a + k x + c sign(v) |v|^α        (α = 1: a linear viscous damper)
//
// Plants, the command c(t) delayed by a pure delay τ (`delay`) and held between ticks:
//   ideal             x = c(t − τ) − p0 at once; v from the last two ticks; a = 0.
//   electromechanical a first-order lag T:  ẋ = (c(t − τ) − p0 − x)/T, a = −v/T within a hold.
//   servo_hydraulic   the vRTHS benchmark plant (Silva et al. 2020, Mech. Syst. Signal Process.
//                     144), command → displacement with control–structure interaction:
//                        u = g·(c(t − τ) − p0),   e = u − x
//                        Gs:  ẅ + β1 ẇ + β2 w = a1β0 e            (servo valve)
//                        Ga:  Ḟ + a3 F = w − a2 v                 (actuator; a2 v: CSI)
//                        specimen: m v̇ = F − k x − c sign(v)|v|^α,  ẋ = v
//                     i.e. x/c = g·Gs·H/(1 + Gs·H), H = Ga·Gsp/(1 + a2 s Ga Gsp), Gsp the
//                     specimen's 1/(m s² + c s + k); the force measured is the actuator's F.
//                     Nominal constants: a1β0 = 2.1283e13, a2 = 4.2297e6, β1 = 425,
//                     β2 = 9.9976e4, a3 = 3.3, g = 1.0261. Needs m > 0.
// The continuous plants are integrated with classical RK4 at the plant's own rate (`rate_hz`,
// 4096 Hz as in the benchmark): each interval between two commands is cut into the fewest
// equal substeps no longer than 1/rate_hz. The delayed command is sampled at the start of each
// substep, so τ is resolved to one substep.
#include <array>
#include <complex>
#include <string>
#include <vector>

#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer {

enum class PlantKind { kIdeal, kElectromechanical, kServoHydraulic };
const char* PlantKindName(PlantKind kind);

struct SpecimenLaw {
  double mass = 0.0;              // m [kg]
  double stiffness = 0.0;         // k [N/m]
  double damping = 0.0;           // c [N·(s/m)^α]
  double damping_exponent = 1.0;  // α [-], > 0
  // f(x, v, a). Unit: [N].
  double Force(double x, double v, double a) const;
};

struct ServoHydraulicConstants {
  double a1_beta0 = 2.1283e13;
  double a2 = 4.2297e6;
  double beta1 = 425.0;
  double beta2 = 9.9976e4;
  double a3 = 3.3;
  double gain = 1.0261;
};

struct RtPlantConfig {
  PlantKind kind = PlantKind::kIdeal;
  double delay = 0.0;     // pure delay τ [s]
  double lag = 0.0;       // electromechanical time constant T [s]
  double rate_hz = 4096;  // integration rate of the continuous plants [Hz]
  double p0 = 0.0;        // zero-force position [m]
  SpecimenLaw specimen;
  ServoHydraulicConstants servo;
};

// Throws ConfigError naming the field (`where` prefixes the message).
void ValidateRtPlantConfig(const RtPlantConfig& config, const std::string& where);

class RtPlant final : public TransferSystem {
 public:
  explicit RtPlant(RtPlantConfig config);

  void Activate() override { active_ = true; }
  int num_actuators() const override { return 1; }
  void Execute(std::span<const double> commands, std::span<Measurement> out) override;
  void Hold() noexcept override { active_ = false; }
  void Deactivate() override { active_ = false; }
  BenchUnits bench_units() const override { return BenchUnits{}; }
  std::string Describe() const override;
  std::optional<std::vector<Measurement>> ReadAll() const override {
    return std::vector<Measurement>{last_};
  }
  BenchAnnouncement Announce() const override;
  std::optional<long> commands_received() const override { return commands_; }
  void StartPaced(double tick, const Clock& clock) override;
  bool can_run_paced() const override { return true; }
  TransferSystem* served_plant() override { return this; }
  // −arg FrequencyResponse(ω)/ω, plus half a tick of hold for the continuous plants. [s]
  std::optional<double> PhaseDelay(double omega, double tick) const override;

  // Static (settled) displacement from p0 for a command displacement u from p0. Unit: [m].
  double SettledDisplacement(double u) const;
  const RtPlantConfig& config() const { return config_; }
  // The plant's command → position response at ω [rad/s], its delay included (the linear
  // damper, α = 1, for the servo plant's specimen).
  std::complex<double> FrequencyResponse(double omega) const;

 private:
  using State = std::array<double, 5>;  // servo: w, ẇ, F, x, v; lag: -, -, -, x, v
  // One command [m]: the settled response, or on a paced run the plant advanced to now.
  Measurement Step(double command);
  void Advance(double t);
  double DelayedCommand(double s) const;
  void Rates(const State& y, double u, State& dy) const;
  Measurement Measure(double t) const;

  RtPlantConfig config_;
  bool active_ = false;
  const Clock* clock_ = nullptr;
  double tick_ = 0.0;
  double t_ = 0.0;  // plant time [s]
  State y_{};
  double x_prev_ = 0.0, t_prev_ = 0.0;  // ideal: the last tick's displacement, for v
  // The commands with their times, a ring that covers the delay (preallocated).
  std::vector<double> hist_t_, hist_c_;
  std::size_t hist_head_ = 0, hist_size_ = 0;
  double initial_command_ = 0.0;
  long commands_ = 0;
  Measurement last_{};
};

}  // namespace hybridtest::transfer
