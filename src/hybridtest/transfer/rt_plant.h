#pragma once
// RtPlant: emulated actuators and their specimen for real-time hybrid testing (transfer type
// `rt_plant`), for n ≥ 1 actuators driving one coupled specimen (n = 1 is the ordinary case). In
// a paced run (StartPaced) every Execute advances the plant to clock.Now() holding the previous
// commands (zero-order hold), then records the new commands and returns the measurements at
// Now(); without StartPaced every Execute is a settled move (a pseudo-dynamic test): positions =
// the plant's static response, forces = the static forces. Speaks SI (m, N). Positions are
// absolute; the plant's state is the displacement x_i of actuator i from its p0_i.
//
// Specimen, in actuator coordinates (x, v = ẋ, a = ẍ, f the load cells' forces, n-vectors):
//     f_i = m_i a_i + Σ_j K_ij x_j + Σ_j C_ij sign(v_j) |v_j|^α      (α = 1: linear viscous)
// m_i the mass moved by actuator i, K and C n × n: the actuators interact through the specimen
// (an off-diagonal K_ij loads actuator i when actuator j moves). With a setup a − p0 = T d the
// slots see Tᵀ K T.
//
// Plants, per actuator (one kind for all, each actuator its own delay τ_i, lag T_i and
// servo constants), the command c_i(t) delayed by τ_i and held between ticks:
//   ideal             x_i = c_i(t − τ_i) − p0_i at once; v from the last two ticks; a = 0.
//   electromechanical a first-order lag T_i:  ẋ_i = (c_i(t − τ_i) − p0_i − x_i)/T_i,
//                     a_i = −v_i/T_i within a hold.
//   servo_hydraulic   the vRTHS benchmark plant (Silva et al. 2020, Mech. Syst. Signal Process.
//                     144) per actuator, command → displacement with control–structure
//                     interaction through the coupled specimen:
//                        u_i = g_i·(c_i(t − τ_i) − p0_i),   e_i = u_i − x_i
//                        Gs:  ẅ_i + β1 ẇ_i + β2 w_i = a1β0 e_i      (servo valve)
//                        Ga:  Ḟ_i + a3 F_i = w_i − a2 v_i            (actuator; a2 v: CSI)
//                        specimen: m_i v̇_i = F_i − Σ_j K_ij x_j − Σ_j C_ij sign(v_j)|v_j|^α
//                     For one actuator x/c = g·Gs·H/(1 + Gs·H), H = Ga·Gsp/(1 + a2 s Ga Gsp),
//                     Gsp = 1/(m s² + c s + k); for n, G(s) = (Zs + Ga(Gs + a2 s))⁻¹ Ga Gs g with
//                     Zs = M s² + C s + K and the others diagonal. The force measured is the
//                     actuator's F_i. Nominal constants: a1β0 = 2.1283e13, a2 = 4.2297e6,
//                     β1 = 425, β2 = 9.9976e4, a3 = 3.3, g = 1.0261. Needs every m_i > 0.
// The continuous plants are integrated with classical RK4 at the plant's own rate (`rate_hz`,
// 4096 Hz as in the benchmark): each interval between two commands is cut into the fewest
// equal substeps no longer than 1/rate_hz. The delayed commands are sampled at the start of each
// substep, so τ_i is resolved to one substep.
#include <complex>
#include <string>
#include <vector>

#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer {

enum class PlantKind { kIdeal, kElectromechanical, kServoHydraulic };
const char* PlantKindName(PlantKind kind);

// The specimen in actuator coordinates, n actuators (see above). Units: m_i [kg], K [N/m],
// C [N·(s/m)^α], α [-] > 0; K and C row-major n × n.
struct SpecimenLaw {
  std::vector<double> mass{0.0};
  std::vector<double> stiffness{0.0};
  std::vector<double> damping{0.0};
  double damping_exponent = 1.0;

  // One actuator: f = m a + k x + c sign(v)|v|^α.
  static SpecimenLaw One(double mass, double stiffness, double damping,
                         double damping_exponent = 1.0);
  int size() const { return static_cast<int>(mass.size()); }
  // f_i(x, v, a_i) for the n-vectors x [m] and v [m/s]. Unit: [N].
  double Force(int i, const double* x, const double* v, double a_i) const;
  // One actuator: f(x, v, a). Unit: [N].
  double Force(double x, double v, double a) const { return Force(0, &x, &v, a); }
};

struct ServoHydraulicConstants {
  double a1_beta0 = 2.1283e13;
  double a2 = 4.2297e6;
  double beta1 = 425.0;
  double beta2 = 9.9976e4;
  double a3 = 3.3;
  double gain = 1.0261;
};

// One actuator's own plant.
struct ActuatorPlant {
  double delay = 0.0;  // pure delay τ [s]
  double lag = 0.0;    // electromechanical time constant T [s]
  double p0 = 0.0;     // zero-force position [m]
  ServoHydraulicConstants servo;
};

struct RtPlantConfig {
  PlantKind kind = PlantKind::kIdeal;
  double rate_hz = 4096;                    // integration rate of the continuous plants [Hz]
  std::vector<ActuatorPlant> actuators{{}};  // one per actuator (n ≥ 1)
  SpecimenLaw specimen;                      // n × n, the actuators' specimen

  int size() const { return static_cast<int>(actuators.size()); }
  // The first (for one actuator: the) actuator's plant.
  ActuatorPlant& one() { return actuators.front(); }
};

// Throws ConfigError naming the field (`where` prefixes the message), actuator k as
// "actuator k" (1-based) when there are several.
void ValidateRtPlantConfig(const RtPlantConfig& config, const std::string& where);

class RtPlant final : public TransferSystem {
 public:
  explicit RtPlant(RtPlantConfig config);

  void Activate() override { active_ = true; }
  int num_actuators() const override { return n_; }
  void Execute(std::span<const double> commands, std::span<Measurement> out) override;
  void Hold() noexcept override { active_ = false; }
  void Deactivate() override { active_ = false; }
  BenchUnits bench_units() const override { return BenchUnits{}; }
  std::string Describe() const override;
  std::optional<std::vector<Measurement>> ReadAll() override { return last_; }
  BenchAnnouncement Announce() const override;
  std::optional<long> commands_received() const override { return commands_; }
  void StartPaced(double tick, const Clock& clock) override;
  bool can_run_paced() const override { return true; }
  TransferSystem* served_plant() override { return this; }
  // The largest over the actuators of −arg G_ii(ω)/ω (G_ii: actuator i's command → its
  // position, the others' commands held), plus half a tick of hold for the continuous plants.
  // Unit: [s].
  std::optional<double> PhaseDelay(double omega, double tick) const override;

  // Static (settled) displacements x from p0 for command displacements u from p0 (n each).
  // Unit: [m].
  std::vector<double> SettledDisplacement(const std::vector<double>& u) const;
  const RtPlantConfig& config() const { return config_; }
  // The plant's command → position response G_ij at ω [rad/s] (actuator j's command to actuator
  // i's position), delays included (the linear damper, α = 1, for the servo plant's specimen).
  std::complex<double> FrequencyResponse(double omega, int i = 0, int j = 0) const;

 private:
  // One command per actuator [m]: the settled response, or on a paced run the plant advanced to
  // now; fills last_.
  void Step(std::span<const double> commands);
  void Advance(double t);
  double DelayedCommand(int i, double s) const;
  void Rates(const double* y, const double* u, double* dy) const;
  void Measure(double t);

  RtPlantConfig config_;
  int n_ = 1;
  bool active_ = false;
  const Clock* clock_ = nullptr;
  double tick_ = 0.0;
  double t_ = 0.0;  // plant time [s]
  // State, 5 per actuator (servo: w, ẇ, F, x, v; lag: -, -, -, x, v), and the RK4 work space.
  std::vector<double> y_, k1_, k2_, k3_, k4_, tmp_, u_;
  std::vector<double> x_prev_;  // ideal: the last tick's displacements, for v
  double t_prev_ = 0.0;
  mutable std::vector<double> xs_, vs_;  // work space of Rates and Measure
  // The commands with their times, a ring that covers the longest delay (preallocated); the
  // commands of entry k are hist_c_[k n … k n + n − 1].
  std::vector<double> hist_t_, hist_c_;
  std::size_t hist_head_ = 0, hist_size_ = 0;
  std::vector<double> initial_command_;
  long commands_ = 0;
  std::vector<Measurement> last_;
};

}  // namespace hybridtest::transfer
