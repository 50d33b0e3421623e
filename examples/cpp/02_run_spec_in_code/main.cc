// A run written in C++, no YAML: the blade tip of examples/06_blade_two_actuators built with
// the multibody API, both its slots (flap and edge) served by one specimen on two actuators of
// an emulated bench (a − p0 = T d), Heun at 1 ms for 10 s. The run opens through the front door
// (lock, output guards, disk budget, record, provenance), is stepped to the end and writes the
// journal `hybridtest run examples/06_blade_two_actuators/emulated.yaml` writes.
//   run_spec_in_code OUT.csv
#include <cmath>
#include <cstdio>
#include <exception>
#include <memory>
#include <string>
#include <utility>

#include <hybridtest/constitutive/linear_spring.h>
#include <hybridtest/hybridtest.h>
#include <hybridtest/integrators/catalogue.h>
#include <hybridtest/transfer/emulated_bench.h>

namespace hb = hybridtest;
namespace rn = hybridtest::runner;
using hb::multibody::ScalarField;
using hb::multibody::Vector3;

// The model: a tip of mass m deflecting in flap (x) and edge (y) on a rotor turning at Ω,
// loaded by a ramped flap load and the edgewise weight, held by two restoring forces (SI).
hb::models::BuiltModel BladeTip() {
  const double m = 4.0, k_f = 5000, k_e = 5000, c_f = 6.0, c_e = 4.0;  // kg, N/m, N·s/m
  const double F0 = 40.0, F1 = 15.0, g = 9.81, Omega = 2.0, t0 = 0.5;  // N, m/s², rad/s, s
  hb::models::ParameterSet p;
  p.Add("m", m, "kg", "blade-tip modal mass");
  p.Add("k_f", k_f, "N/m", "flap stiffness (default numerical substructure)");
  p.Add("k_e", k_e, "N/m", "edge stiffness (default numerical substructure)");
  p.Add("c_f", c_f, "N·s/m", "flap damping");
  p.Add("c_e", c_e, "N·s/m", "edge damping");
  p.Add("F0", F0, "N", "mean aerodynamic flap load");
  p.Add("F1", F1, "N", "once-per-revolution flap load amplitude");
  p.Add("g", g, "m/s²", "gravity");
  p.Add("Omega", Omega, "rad/s", "rotor speed");
  p.Add("t0", t0, "s", "load ramp time constant");
  hb::multibody::ModelBuilder b(
      {{"q_flap", "m", "flap deflection of the tip (out of plane)"},
       {"q_edge", "m", "edge deflection of the tip (in plane)"}},
      {{"u1", "m/s", "time derivative of q_flap"}, {"u2", "m/s", "time derivative of q_edge"}});
  const int ramp = b.AddTimeFunction("ramp", [t0](const auto& t) {
    using T = std::decay_t<decltype(t)>;
    using std::exp;
    return T(1.0 - exp(-t / t0));
  });
  const auto P = b.AddPoint("P", b.origin(), b.newtonian(),
                            {ScalarField::Coordinate(0), ScalarField::Coordinate(1), {}});
  b.AddParticle("tip", P, m);
  b.AddRestoringForceSlot("r_flap", "flap restoring force", ScalarField::Coordinate(0));
  b.AddRestoringForceSlot("r_edge", "edge restoring force", ScalarField::Coordinate(1));
  b.AddForce("flap", P, b.newtonian(), [=](const auto& a) {
    using T = std::decay_t<decltype(a.t)>;
    using std::sin;
    const T load = a.time_function(ramp) * (F0 + F1 * sin(Omega * a.t));
    return Vector3<T>(-a.r[0] - c_f * a.u[0] + load, T(0.0), T(0.0));
  });
  b.AddForce("edge", P, b.newtonian(), [=](const auto& a) {
    using T = std::decay_t<decltype(a.t)>;
    using std::sin;
    const T load = a.time_function(ramp) * m * g * sin(Omega * a.t);
    return Vector3<T>(T(0.0), -a.r[1] - c_e * a.u[1] + load, T(0.0));
  });
  return {"blade_tip", "a blade tip with two deflections, flap and edge (in code)", std::move(p),
          std::move(b).Build(), {k_f, k_e}};
}

// One actuator of the ideal bench (bench-2act.yaml's values, in its units): no lag, no delay,
// no noise, one sample per command. `k`: the specimen's stiffness along this actuator [N/m].
hb::transfer::EmulatedBenchConfig Actuator(double p0_mm, unsigned long seed, double k) {
  const double mm = hb::units::kMillimetre, ms = hb::units::kMillisecond;
  const double kN = hb::units::kKilonewton;
  hb::transfer::EmulatedBenchConfig a = hb::transfer::DefaultEmulatedBenchConfig();
  a.seed = seed;
  a.p0 = a.initial_position = p0_mm * mm;
  a.specimen = std::make_shared<hb::constitutive::LinearSpring>(k, "specimen axis");
  a.position_min = -150 * mm;
  a.position_max = 150 * mm;
  a.capacity = 10 * kN;
  a.velocity_limit = 1000 * mm;  // [m/s]
  a.lag.type = hb::transfer::ServoLag::Type::kNone;
  a.delay = 0 * ms;
  a.noise_std = a.resolution = a.offset = 0.0;
  a.settle_tolerance = 0.001 * mm;
  a.settle_dwell = 0 * ms;
  a.sampling_window = 1 * ms;
  a.overhead = 0 * ms;
  a.internal_step = 1 * ms;
  a.safety = {-150 * mm, 150 * mm, 5 * mm, 8 * kN, 10 * kN, 5.0};  // the bench's own limits
  return a;
}

// The specimen: both slots on two actuators, actuator 1 in flap, actuator 2 at an angle.
hb::substructures::SubstructureSpec Specimen() {
  hb::transfer::EmulatedBenchSpec bench;
  bench.stiffness.resize(2, 2);
  bench.stiffness << 5000, 1200, 1200, 3000;  // in actuator coordinates [N/m]
  bench.specimen = std::make_shared<hb::constitutive::LinearCoupledLaw>(bench.stiffness);
  bench.actuators = {Actuator(20, 1, 5000), Actuator(30, 2, 3000)};

  hb::substructures::PhysicalSpec physical;
  physical.transfer = {"emulated", [bench]() -> std::unique_ptr<hb::transfer::TransferSystem> {
                         return std::make_unique<hb::transfer::EmulatedBench>(bench);
                       }};
  hb::substructures::LinearSetup setup;
  setup.p0 = Eigen::Vector2d(0.020, 0.030);                     // [m]
  setup.transform.resize(2, 2);
  setup.transform << 1.0, 0.0, 0.6, 0.8;                       // a − p0 = T d
  setup.load_cell_zero = Eigen::Vector2d::Zero();              // [N]
  physical.linear = setup;
  hb::transfer::SafetyLimits limits;                           // SI: m, N, s
  limits.stroke_min = -0.10;
  limits.stroke_max = 0.10;
  limits.max_increment = 0.002;
  limits.force_soft = 2000;
  limits.force_hard = 3000;
  limits.timeout = 5;
  physical.actuator_limits = {limits, limits};
  physical.limits = limits;

  hb::substructures::SubstructureSpec spec;
  spec.slot = "blade1";  // its journal channels: blade1_1_command, ...
  spec.slots = {"r_flap", "r_edge"};
  spec.physical = std::move(physical);
  return spec;
}

int main(int argc, char** argv) {
  if (argc != 2) return std::fprintf(stderr, "usage: run_spec_in_code OUT.csv\n"), 2;
  try {
    hb::io::RunSpec spec(BladeTip());
    spec.x0 = Eigen::VectorXd::Zero(spec.model.model.num_states());
    spec.scheme.config.kind = hb::schemes::SchemeKind::kRungeKutta;
    spec.scheme.tableau = hb::integrators::FindTableau("heun");
    spec.scheme.dt = 0.001;                                    // [s]
    spec.scheme.duration = 10.0;                               // [s]
    spec.scheme.steps = hb::io::StepCount(spec.scheme.duration, spec.scheme.dt);
    spec.substructures = {Specimen()};
    spec.output.csv_path = argv[1];
    spec.output.command = "run";
    spec.source.name = "run_spec_in_code";
    spec.quiet = true;

    // The front door: nothing is built, activated or moved before it has passed.
    rn::OpenedRun opened = rn::OpenRun(spec, {.command_line = "run_spec_in_code"});
    rn::Session session(std::move(spec), std::move(opened));  // it holds the run's lock
    rn::StepResult result = session.Initialize();
    while (result.status == rn::SessionStatus::kWorking) result = session.Step();
    if (result.status != rn::SessionStatus::kFinished) {
      std::fprintf(stderr, "%s: %s\n", rn::StatusName(result.status), result.reason.c_str());
      return 1;
    }
    const hb::schemes::CommittedPoint& last = session.committed();
    std::printf("final state at step %ld, t = %.17g s:\n", last.step, last.t);
    for (int i = 0; i < session.model().num_coordinates(); ++i)
      std::printf("  q%d = %.17g\n", i + 1, last.x[i]);
    const rn::RunStatistics& s = session.statistics();
    std::printf("statistics: %ld steps, %ld rows, %ld physical evaluations -> %s\n", s.steps,
                s.rows, s.physical_evaluations, argv[1]);
  } catch (const hybridtest::ConfigError& e) {
    return std::fprintf(stderr, "%s\n", e.what()), 2;
  } catch (const std::exception& e) {
    return std::fprintf(stderr, "%s\n", e.what()), 1;
  }
}
