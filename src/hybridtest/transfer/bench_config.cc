#include "hybridtest/transfer/bench_config.h"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <numbers>

#include "hybridtest/common/error.h"
#include "hybridtest/common/units.h"
#include "hybridtest/common/yaml_input.h"
#include "hybridtest/constitutive/cantilever.h"
#include "hybridtest/constitutive/parse_law.h"
#include "hybridtest/transfer/bench_spec.h"

namespace hybridtest::transfer {
namespace {

using units::kKilonewton;
using units::kMillimetre;
using units::kMillisecond;

constexpr std::size_t kMaxFaults = 10000;          // entries of `faults:`
constexpr long long kMaxSeed = 1LL << 53;          // integers a double holds exactly

// A sub-mapping with only `allowed` keys; an undefined node when absent.
// A value the config gives in `unit` (e.g. kMillimetre for a key ending in _mm), returned in
// SI; `si_default` (SI) when the key is absent.
double ReadInUnit(const YamlInput& in, const YAML::Node& node, std::string_view path,
                  const std::string& key, std::string_view expected, double si_default,
                  double unit) {
  return in.ReadNumber(node, path, key, expected, si_default / unit) * unit;
}

YAML::Node SubMapping(const YamlInput& in, const YAML::Node& node, std::string_view where,
                      const std::string& key, std::initializer_list<std::string_view> allowed) {
  const std::string path = JoinKeyPath(where, key);
  YAML::Node sub = in.Mapping(node, key, path, false);
  if (sub) in.CheckKeys(sub, path, allowed);
  return sub;
}

void ParseUnits(const YamlInput& in, const YAML::Node& node, std::string_view where,
                BenchUnits& units) {
  const std::string length = in.ReadString(node, where, "length", "mm");
  const std::string force = in.ReadString(node, where, "force", "N");
  if (length == "mm") {
    units.metres_per_length_unit = kMillimetre;
  } else if (length == "m") {
    units.metres_per_length_unit = 1.0;
  } else {
    in.ThrowValue(node["length"], JoinKeyPath(where, "length"), "mm or m");
  }
  if (force == "N") {
    units.newtons_per_force_unit = 1.0;
  } else if (force == "kN") {
    units.newtons_per_force_unit = kKilonewton;
  } else {
    in.ThrowValue(node["force"], JoinKeyPath(where, "force"), "N or kN");
  }
  units.length_name = length;
  units.force_name = force;
}

void ParseLag(const YamlInput& in, const YAML::Node& node, std::string_view where, ServoLag& lag) {
  in.RequireMapping(node, where);
  in.CheckKeys(node, where, {"type", "time_constant_ms", "natural_frequency_hz", "damping_ratio"});
  const std::string type = in.ReadString(node, where, "type", "second_order");
  if (type == "none") {
    lag.type = ServoLag::Type::kNone;
  } else if (type == "first_order") {
    lag.type = ServoLag::Type::kFirstOrder;
    lag.time_constant =
        in.ReadNumber(node, where, "time_constant_ms", "a positive time constant in ms") *
        kMillisecond;
  } else if (type == "second_order") {
    lag.type = ServoLag::Type::kSecondOrder;
    lag.natural_frequency =
        in.ReadNumber(node, where, "natural_frequency_hz", "a positive natural frequency in Hz",
                      lag.natural_frequency);
    lag.damping_ratio =
        in.ReadNumber(node, where, "damping_ratio", "a positive damping ratio", lag.damping_ratio);
  } else {
    in.ThrowValue(node["type"], JoinKeyPath(where, "type"), "none, first_order or second_order");
  }
}

void ParseFaults(const YamlInput& in, const YAML::Node& node, std::string_view where,
                 std::vector<Fault>& faults) {
  const std::string expected =
      "a list of {at: N, kind: nan|inf|spike|silence, force_N: F} (N: 1-based command index)";
  if (!node.IsSequence()) in.ThrowValue(node, where, expected);
  if (node.size() > kMaxFaults) {
    throw ConfigError(fmt::format("{}: {} faults; at most {} are allowed", where, node.size(),
                                  kMaxFaults));
  }
  for (std::size_t i = 0; i < node.size(); ++i) {
    const std::string path = fmt::format("{}[{}]", where, i);
    const YAML::Node entry = node[i];
    in.RequireMapping(entry, path);
    in.CheckKeys(entry, path, {"at", "kind", "force_N"});
    Fault fault;
    fault.command = static_cast<long>(in.Count(entry["at"], JoinKeyPath(path, "at"),
                                               "a 1-based command index", 1, kMaxFaultCommand));
    const std::string kind = in.ReadString(entry, path, "kind", "");
    const std::string kind_path = JoinKeyPath(path, "kind");
    const bool known = kind == "nan" || kind == "inf" || kind == "spike" || kind == "silence";
    if (!known) {
      in.ThrowValue(entry["kind"], kind_path,
                    "one of nan, inf, spike, silence (the wire faults corrupt, stale_seq, "
                    "duplicate and close are injected with `hybridtest bench --inject`)");
    }
    fault.kind = ParseFaultKind(kind, kind_path);
    fault.spike_force = in.ReadNumber(entry, path, "force_N", "a force in N", fault.spike_force);
    faults.push_back(fault);
  }
}

}  // namespace

BenchUnits ParseBenchUnits(const YAML::Node& units, std::string_view where) {
  const YamlInput in = YamlInput::ForNode(units);
  in.RequireMapping(units, where);
  in.CheckKeys(units, where, {"length", "force"});
  BenchUnits result;
  ParseUnits(in, units, where, result);
  return result;
}

EmulatedBenchConfig DefaultEmulatedBenchConfig() {
  EmulatedBenchConfig config;
  config.specimen = constitutive::MakeCantileverSpring(0.5, 0.1, 0.005, 210e9);
  return config;
}

EmulatedBenchConfig ParseEmulatedBenchConfig(const YAML::Node& bench, std::string_view where) {
  EmulatedBenchConfig c = DefaultEmulatedBenchConfig();
  const YamlInput in = YamlInput::ForNode(bench);
  in.RequireMapping(bench, where);
  in.CheckKeys(bench, where,
               {"units", "seed", "pacing", "p0_mm", "initial_position_mm", "specimen", "actuator",
                "load_cell", "settling", "sampling", "timing", "safety", "faults",
                "openfresco"});
  // Top level.
  if (auto n = SubMapping(in, bench, where, "units", {"length", "force"})) {
    ParseUnits(in, n, JoinKeyPath(where, "units"), c.units);
  }
  if (bench["seed"]) {
    c.seed = static_cast<unsigned long>(in.Count(bench["seed"], JoinKeyPath(where, "seed"),
                                                 "a non-negative integer", 0, kMaxSeed));
  }
  const std::string pacing = in.ReadString(bench, where, "pacing", "accelerated");
  if (pacing != "accelerated" && pacing != "realtime") {
    in.ThrowValue(bench["pacing"], JoinKeyPath(where, "pacing"), "accelerated or realtime");
  }
  c.realtime = pacing == "realtime";
  c.p0 = ReadInUnit(in, bench, where, "p0_mm", "a position in mm", c.p0, kMillimetre);
  c.initial_position =
      ReadInUnit(in, bench, where, "initial_position_mm", "a position in mm", c.p0, kMillimetre);
  if (bench["specimen"]) {
    c.specimen = constitutive::ParseRestoringForceLaw(bench["specimen"],
                                                      JoinKeyPath(where, "specimen"));
  }
  // Actuator.
  if (auto n = SubMapping(in, bench, where, "actuator",
                          {"position_min_mm", "position_max_mm", "capacity_kN",
                           "velocity_limit_mm_per_s", "lag", "delay_ms", "approach"})) {
    const std::string path = JoinKeyPath(where, "actuator");
    c.position_min = ReadInUnit(in, n, path, "position_min_mm", "a position in mm",
                                c.position_min, kMillimetre);
    c.position_max = ReadInUnit(in, n, path, "position_max_mm", "a position in mm",
                                c.position_max, kMillimetre);
    c.capacity = ReadInUnit(in, n, path, "capacity_kN", "a positive force in kN", c.capacity,
                            kKilonewton);
    c.velocity_limit = ReadInUnit(in, n, path, "velocity_limit_mm_per_s",
                                  "a positive speed in mm/s", c.velocity_limit, kMillimetre);
    if (n["lag"]) ParseLag(in, n["lag"], JoinKeyPath(path, "lag"), c.lag);
    c.delay =
        ReadInUnit(in, n, path, "delay_ms", "a non-negative delay in ms", c.delay, kMillisecond);
    if (n["approach"]) {
      const std::string approach = in.String(n["approach"], JoinKeyPath(path, "approach"),
                                             "direct or monotone");
      if (approach == "direct") {
        c.approach = Approach::kDirect;
      } else if (approach == "monotone") {
        c.approach = Approach::kMonotone;
      } else {
        throw ConfigError(fmt::format(
            "{} = '{}': expected direct (the servo follows the ramp; an underdamped lag "
            "overshoots) or monotone (every target approached without overshoot)",
            in.Where(n["approach"], JoinKeyPath(path, "approach")), approach));
      }
    }
  }
  // Load cell.
  if (auto n =
          SubMapping(in, bench, where, "load_cell", {"noise_std_N", "resolution_N", "offset_N"})) {
    const std::string path = JoinKeyPath(where, "load_cell");
    c.noise_std = in.ReadNumber(n, path, "noise_std_N", "a non-negative force in N", c.noise_std);
    c.resolution =
        in.ReadNumber(n, path, "resolution_N", "a non-negative force in N", c.resolution);
    c.offset = in.ReadNumber(n, path, "offset_N", "a force in N", c.offset);
  }
  // Settling, sampling, timing.
  if (auto n = SubMapping(in, bench, where, "settling", {"tolerance_mm", "dwell_ms"})) {
    const std::string path = JoinKeyPath(where, "settling");
    c.settle_tolerance = ReadInUnit(in, n, path, "tolerance_mm", "a positive length in mm",
                                    c.settle_tolerance, kMillimetre);
    c.settle_dwell = ReadInUnit(in, n, path, "dwell_ms", "a non-negative time in ms",
                                c.settle_dwell, kMillisecond);
  }
  if (auto n = SubMapping(in, bench, where, "sampling", {"window_ms"})) {
    c.sampling_window =
        ReadInUnit(in, n, JoinKeyPath(where, "sampling"), "window_ms",
                   "a non-negative time in ms", c.sampling_window, kMillisecond);
  }
  if (auto n = SubMapping(in, bench, where, "timing", {"overhead_ms", "internal_step_ms"})) {
    const std::string path = JoinKeyPath(where, "timing");
    c.overhead = ReadInUnit(in, n, path, "overhead_ms", "a non-negative time in ms", c.overhead,
                            kMillisecond);
    c.internal_step = ReadInUnit(in, n, path, "internal_step_ms", "a positive time in ms",
                                 c.internal_step, kMillisecond);
  }
  // Safety: defaults follow the actuator.
  c.safety.stroke_min = c.position_min;
  c.safety.stroke_max = c.position_max;
  c.safety.force_hard = c.capacity;
  c.safety.force_soft = std::min(c.safety.force_soft, c.capacity);
  if (auto n = SubMapping(in, bench, where, "safety",
                          {"stroke_min_mm", "stroke_max_mm", "max_increment_mm", "force_soft_kN",
                           "force_hard_kN", "timeout_s"})) {
    const std::string path = JoinKeyPath(where, "safety");
    SafetyLimits& s = c.safety;
    s.stroke_min =
        ReadInUnit(in, n, path, "stroke_min_mm", "a position in mm", s.stroke_min, kMillimetre);
    s.stroke_max =
        ReadInUnit(in, n, path, "stroke_max_mm", "a position in mm", s.stroke_max, kMillimetre);
    s.max_increment = ReadInUnit(in, n, path, "max_increment_mm", "a positive length in mm",
                                 s.max_increment, kMillimetre);
    s.force_soft = ReadInUnit(in, n, path, "force_soft_kN", "a positive force in kN",
                              s.force_soft, kKilonewton);
    s.force_hard = ReadInUnit(in, n, path, "force_hard_kN", "a positive force in kN",
                              s.force_hard, kKilonewton);
    s.timeout = in.ReadNumber(n, path, "timeout_s", "a positive time in s", s.timeout);
  }
  if (bench["faults"]) ParseFaults(in, bench["faults"], JoinKeyPath(where, "faults"), c.faults);
  try {
    ValidateEmulatedBenchConfig(c);
  } catch (const ConfigError& e) {
    throw ConfigError(fmt::format("{}: {}", where, e.what()));
  }
  return c;
}

EmulatedBenchConfig LoadEmulatedBenchConfig(const std::string& path) {
  // The one reader of bench files (bench_spec.h), whose one-actuator form is this config.
  EmulatedBenchSpec spec = LoadEmulatedBenchSpec(path);
  if (spec.coupled_safety) {
    throw ConfigError(fmt::format(
        "{}: a bench of {} actuators (`actuators:`); expected the one-actuator form here (see "
        "examples/rotor/bench-ideal.yaml), or load it with LoadEmulatedBenchSpec",
        path, spec.num_actuators()));
  }
  return std::move(spec.actuators.front());
}

void ValidateEmulatedBenchConfig(const EmulatedBenchConfig& c) {
  auto fail = [](const std::string& message) { throw ConfigError(message); };
  if (!c.specimen) fail("specimen: missing; expected a restoring-force law");
  if (!(c.position_min < c.position_max)) {
    fail(fmt::format("actuator.position_min_mm = {} is not below position_max_mm = {}",
                     c.position_min / kMillimetre, c.position_max / kMillimetre));
  }
  if (c.safety.stroke_min < c.position_min || c.safety.stroke_max > c.position_max) {
    fail(fmt::format("safety stroke [{}, {}] mm exceeds the actuator range [{}, {}] mm; narrow "
                     "safety.stroke_min_mm/stroke_max_mm",
                     c.safety.stroke_min / kMillimetre, c.safety.stroke_max / kMillimetre,
                     c.position_min / kMillimetre, c.position_max / kMillimetre));
  }
  if (c.initial_position < c.safety.stroke_min || c.initial_position > c.safety.stroke_max) {
    fail(fmt::format("initial_position_mm = {} is outside the safety stroke [{}, {}] mm",
                     c.initial_position / kMillimetre, c.safety.stroke_min / kMillimetre,
                     c.safety.stroke_max / kMillimetre));
  }
  if (!(c.capacity > 0.0)) {
    fail(fmt::format("actuator.capacity_kN = {}: expected > 0", c.capacity / kKilonewton));
  }
  if (!(c.velocity_limit > 0.0)) {
    fail(fmt::format("actuator.velocity_limit_mm_per_s = {}: expected > 0",
                     c.velocity_limit / kMillimetre));
  }
  // Every timing key is bounded: the emulated bench simulates each command in internal
  // steps, so a tiny step or a huge window would run for hours and ignore Ctrl-C.
  if (!(c.internal_step >= 1e-6 && c.internal_step <= 0.1)) {
    fail(fmt::format("timing.internal_step_ms = {}: expected 0.001 to 100 ms (1 ms is usual)",
                     c.internal_step / kMillisecond));
  }
  auto bounded = [&](double value, double max_s, const char* key) {
    if (!(value >= 0.0 && value <= max_s)) {
      fail(fmt::format("{} = {}: expected 0 to {} ms", key, value / kMillisecond,
                       max_s / kMillisecond));
    }
  };
  bounded(c.delay, 10.0, "actuator.delay_ms");
  bounded(c.settle_dwell, 60.0, "settling.dwell_ms");
  bounded(c.sampling_window, 60.0, "sampling.window_ms");
  bounded(c.overhead, 3600.0, "timing.overhead_ms");
  if ((c.delay + c.settle_dwell + c.sampling_window) / c.internal_step > 1e7) {
    fail(fmt::format("actuator.delay_ms + settling.dwell_ms + sampling.window_ms = {} ms is "
                     "more than 10 million internal steps of {} ms per command; lengthen "
                     "timing.internal_step_ms or shorten the windows",
                     (c.delay + c.settle_dwell + c.sampling_window) / kMillisecond,
                     c.internal_step / kMillisecond));
  }
  if (c.lag.type == ServoLag::Type::kFirstOrder && c.lag.time_constant > 10.0) {
    fail("actuator.lag.time_constant_ms: expected at most 10000 ms");
  }
  if (c.delay < 0.0) fail("actuator.delay_ms: expected >= 0");
  if (c.noise_std < 0.0) fail("load_cell.noise_std_N: expected >= 0");
  if (c.resolution < 0.0) fail("load_cell.resolution_N: expected >= 0 (0 disables quantisation)");
  if (!(c.settle_tolerance > 0.0)) fail("settling.tolerance_mm: expected > 0");
  if (c.settle_dwell < 0.0 || c.sampling_window < 0.0 || c.overhead < 0.0) {
    fail("settling.dwell_ms, sampling.window_ms and timing.overhead_ms: expected >= 0");
  }
  // The explicit lag integration needs a step well below the lag's time scale.
  if (c.lag.type == ServoLag::Type::kFirstOrder && !(c.lag.time_constant > 0.0)) {
    fail("actuator.lag.time_constant_ms: expected > 0");
  }
  if (c.lag.type == ServoLag::Type::kSecondOrder) {
    const double omega = 2.0 * std::numbers::pi * c.lag.natural_frequency;
    if (!(c.lag.natural_frequency > 0.0) || !(c.lag.damping_ratio > 0.0)) {
      fail("actuator.lag: expected natural_frequency_hz > 0 and damping_ratio > 0");
    }
    if (omega * c.internal_step > 0.2) {
      fail(fmt::format("actuator.lag.natural_frequency_hz = {} is too fast for "
                       "timing.internal_step_ms = {}: need 2π·f·step <= 0.2; reduce the step",
                       c.lag.natural_frequency, c.internal_step / kMillisecond));
    }
  }
  SafetyMonitor check(c.safety);  // throws ConfigError on inconsistent limits
  (void)check;
}

}  // namespace hybridtest::transfer
