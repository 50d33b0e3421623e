#pragma once
// Configuration of one actuator of the emulated test bench (EmulatedBench; EmulatedBenchSpec in
// bench_spec.h holds one per actuator and the specimen). Loaded from the `bench:` mapping of
// a YAML file. Config keys carry their unit in the name when it is not SI; the struct below is
// SI throughout (conversion happens once, in the parser).
//
//   bench:
//     units: {length: mm, force: N}   # units spoken on the wire: length mm|m, force N|kN
//     seed: 1                         # load-cell RNG seed (runs are reproducible)
//     pacing: accelerated             # accelerated (compute, report lab time) | realtime (sleep)
//     p0_mm: 0                        # actuator position of zero specimen force [mm]
//     initial_position_mm: 0          # actuator position at start [mm] (default: p0_mm)
//     specimen: {type: cantilever, length: 0.5, width: 0.1, thickness: 0.005,
//                youngs_modulus: 210e9}  # any law of constitutive/parse_law.h (SI values)
//     actuator:
//       position_min_mm: -150         # lowest reachable position [mm]
//       position_max_mm: 150          # highest reachable position [mm]
//       capacity_kN: 10               # force capacity; beyond it the drive trips [kN]
//       velocity_limit_mm_per_s: 20   # largest speed of the position reference [mm/s]
//       lag: {type: second_order, natural_frequency_hz: 10, damping_ratio: 0.8}
//            # or {type: first_order, time_constant_ms: 20} or {type: none}
//       delay_ms: 2                   # pure transport delay of the servo loop [ms]
//       approach: monotone            # monotone | direct: how a move approaches its target
//                                     # (actuator.h); monotone never overshoots it
//     load_cell:
//       noise_std_N: 0.2              # Gaussian noise of one raw sample, std dev [N]
//       resolution_N: 0.01            # quantisation step of one raw sample [N]; 0: none
//       offset_N: 0                   # constant zero offset [N]
//     settling:
//       tolerance_mm: 0.005           # |target − position| below which the actuator is settled
//       dwell_ms: 100                 # how long it must stay within tolerance [ms]
//     sampling:
//       window_ms: 500                # averaging window of one measurement [ms]
//     timing:
//       overhead_ms: 440              # fixed lab time per command (API, EtherCAT, logging) [ms]
//       internal_step_ms: 1           # step of the internal simulation and sampling rate [ms]
//     safety:                          # the bench's own SafetyMonitor (see safety.h)
//       stroke_min_mm: -150           # default: actuator.position_min_mm
//       stroke_max_mm: 150            # default: actuator.position_max_mm
//       max_increment_mm: 5
//       force_soft_kN: 8
//       force_hard_kN: 10             # default: actuator.capacity_kN
//       timeout_s: 5                  # longest lab time for one command
//     seed: 1                         # load-cell RNG seed, an integer in [0, 2^53]
//     faults:                         # TEST FACILITY ONLY; see bench_faults.h
//       - {at: 100, kind: nan}        # at: 1-based command index; kind: nan|inf|spike|silence
//       - {at: 200, kind: spike, force_N: 1e5}
//     openfresco: {...}               # optional; read by transfer/openfresco/setup_config.h
//
// The defaults are calibrated so that the seed paper's test (20,000 small moves) takes about
// 6 h 16 min of lab time: ~1.13 s per command (see tests/transfer/emulated_bench_test.cc).
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "hybridtest/constitutive/restoring_force_law.h"
#include "hybridtest/transfer/bench_faults.h"
#include "hybridtest/transfer/safety.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer {

// Servo tracking lag of the actuator: how the measured position follows the (rate-limited,
// delayed) position reference.
struct ServoLag {
  enum class Type { kNone, kFirstOrder, kSecondOrder };
  Type type = Type::kSecondOrder;
  double time_constant = 0.02;      // first order: τ ṗ = r − p. Unit: [s].
  double natural_frequency = 10.0;  // second order: p̈ = ωn²(r − p) − 2ζωn ṗ, fn. Unit: [Hz].
  double damping_ratio = 0.8;       // second order: ζ [-].
};

// How the controller approaches a new target (actuator.h).
//   kDirect     the servo follows the rate-limited reference; an underdamped second-order lag
//               overshoots every move (ζ = 0.8: by ~1.5 %), a small load reversal each time;
//   kMonotone   the reference is shaped for the servo lag (a zero-vibration input shaper), so
//               the position approaches every target from the direction of motion, without
//               overshoot (what a pseudo-dynamic test needs; one half period of the lag longer).
// The default is kMonotone: a controller set up for pseudo-dynamic testing approaches each
// target without reversing the load (a hysteretic specimen would ratchet on every overshoot);
// kDirect models an untuned servo loop, for studying what an overshoot does.
enum class Approach { kDirect, kMonotone };

struct EmulatedBenchConfig {
  BenchUnits units{1e-3, 1.0, "mm", "N"};  // wire units (default mm and N)
  unsigned long seed = 1;                  // load-cell RNG seed
  bool realtime = false;                   // pacing: realtime makes Execute sleep
  double p0 = 0.0;                         // zero-force actuator position. Unit: [m].
  double initial_position = 0.0;           // actuator position at start. Unit: [m].
  // The specimen's restoring-force law of the deformation (position − p0); never null.
  std::shared_ptr<const constitutive::RestoringForceLaw> specimen;

  double position_min = -0.150;            // reachable range. Unit: [m].
  double position_max = 0.150;             // Unit: [m].
  double capacity = 10e3;                  // actuator force capacity. Unit: [N].
  double velocity_limit = 0.020;           // Unit: [m/s].
  ServoLag lag;
  double delay = 0.002;                    // pure delay. Unit: [s].
  Approach approach = Approach::kMonotone;  // actuator.approach

  double noise_std = 0.2;                  // load-cell noise per raw sample. Unit: [N].
  double resolution = 0.01;                // load-cell quantisation. Unit: [N]; 0 = none.
  double offset = 0.0;                     // load-cell offset. Unit: [N].

  double settle_tolerance = 0.005e-3;      // Unit: [m].
  double settle_dwell = 0.100;             // Unit: [s].
  double sampling_window = 0.500;          // Unit: [s].
  double overhead = 0.440;                 // fixed lab time per command. Unit: [s].
  double internal_step = 0.001;            // internal simulation step. Unit: [s].

  SafetyLimits safety;                     // the bench's own limits, SI
  std::vector<Fault> faults;               // TEST FACILITY (bench_faults.h): measurement kinds
};

// The default configuration: the paper's cantilever on a realistic bench.
EmulatedBenchConfig DefaultEmulatedBenchConfig();

// Parses the `bench:` mapping itself (not the document holding it). `where` prefixes errors,
// e.g. "bench.yaml: bench". Missing keys take the defaults above. Throws ConfigError naming the
// key path, the value, what was expected and how to fix it.
EmulatedBenchConfig ParseEmulatedBenchConfig(const YAML::Node& bench, std::string_view where);

// Parses a `units: {length: mm|m, force: N|kN}` mapping (missing keys: mm and N). `where` is
// its key path. Throws ConfigError naming the key and the allowed values.
BenchUnits ParseBenchUnits(const YAML::Node& units, std::string_view where);

// Loads a bench file of the one-actuator form: LoadEmulatedBenchSpec (bench_spec.h, the one
// reader of bench files), whose one actuator this is. Throws ConfigError (also for a file of
// the `actuators:` form, an unreadable file or a YAML syntax error, with the line).
EmulatedBenchConfig LoadEmulatedBenchConfig(const std::string& path);

// Throws ConfigError if the configuration is inconsistent (e.g. safety stroke outside the
// actuator range, lag too fast for the internal step). Called by the parser and by the bench.
void ValidateEmulatedBenchConfig(const EmulatedBenchConfig& config);

}  // namespace hybridtest::transfer
