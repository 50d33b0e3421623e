// See physical_slot_config.h.
#include "hybridtest/io/physical_slot_config.h"

#include <fmt/core.h>

#include "hybridtest/common/error.h"
#include "hybridtest/io/transfer_readers.h"
#include "hybridtest/transfer/emulated_bench.h"

namespace hybridtest::io::internal {

using substructures::TransferSpec;

// `reply_timeout` [s]: the safety section's communication timeout, used by a remote transfer
// unless its own `timeout` is given. Everything is read and checked here, once; the spec's
// factory only builds from what was read.
TransferSpec ParseTransfer(const YamlInput& in, const YAML::Node& node, const std::string& kp,
                           const SubstructureOptions& options, double reply_timeout,
                           const transfer::SafetyLimits* limits) {
  if (options.emulate_bench) {  // `plan --emulate`: no real bench, whatever the config names
    TransferSpec emulated = EmulatedTransfer(*options.emulate_bench);
    if (options.files_read != nullptr) {
      options.files_read->push_back({"bench", *options.emulate_bench});
    }
    return emulated;
  }
  return ReadTransfer(
      {in, node, kp, options.bench_address, reply_timeout, limits, options.files_read});
}

// Whether the transfer section `node` talks to a bench over the network (and so takes the
// --bench HOST:PORT address): remote, modbus, openfresco, a compensator around one, or a type
// a program registered (which may read the address; given the benefit of the doubt); not
// the in-process ones (emulated, loopback, rt_plant, an FMU plant).
bool TakesBenchAddress(const YAML::Node& node) {
  if (!node.IsDefined() || !node.IsMap() || !node["type"] || !node["type"].IsScalar()) {
    return false;
  }
  const std::string type = node["type"].Scalar();
  if (type == "remote" || type == "modbus" || type == "openfresco") return true;
  if (type == "compensated") return TakesBenchAddress(node["inner"]);
  return type != "emulated" && type != "loopback" && type != "rt_plant" && type != "fmu";
}

substructures::SetupTransform ParseSetup(const YamlInput& in, const YAML::Node& node,
                                         const std::string& kp) {
  substructures::SetupTransform s;
  if (!node.IsDefined()) return s;
  in.RequireMapping(node, kp);
  in.CheckKeys(node, kp, {"p0", "sign", "scale", "force_sign", "force_scale", "load_cell_zero"});
  s.p0 = in.ReadNumber(node, kp, "p0", "the actuator position at zero specimen force, in m", s.p0);
  s.sign = in.ReadNumber(node, kp, "sign", "+1 or -1", s.sign);
  s.scale = in.ReadNumber(node, kp, "scale", "a positive factor", s.scale);
  s.force_sign = in.ReadNumber(node, kp, "force_sign", "+1 or -1", s.force_sign);
  s.force_scale = in.ReadNumber(node, kp, "force_scale", "a positive factor", s.force_scale);
  s.load_cell_zero = in.ReadNumber(node, kp, "load_cell_zero",
                                   "the load-cell reading at zero load, in N", s.load_cell_zero);
  try {
    s.Validate();
  } catch (const ConfigError& e) {
    throw ConfigError(fmt::format("{}: {}", in.Where(node, kp), e.what()));
  }
  return s;
}

transfer::SafetyLimits ParseSafety(const YamlInput& in, const YAML::Node& node,
                                   const std::string& kp) {
  transfer::SafetyLimits l;
  // A physical slot states its limits, or acknowledges the actuator's defaults in so many
  // words: a forgotten block must not run a specimen on 10 kN limits without anyone knowing.
  if (!node.IsDefined() || node.IsNull()) {
    throw ConfigError(fmt::format(
        "{}: missing; a physical slot needs the limits of its bench: `safety:` with "
        "stroke_min, stroke_max, max_increment [m], force_soft, force_hard [N] and timeout [s] "
        "(docs/safety.md), or `safety: defaults` to accept the defaults (stroke ±{} m, "
        "max_increment {} m, force_soft {} N, force_hard {} N, timeout {} s)",
        in.Where(node, kp), l.stroke_max, l.max_increment, l.force_soft, l.force_hard,
        l.timeout));
  }
  if (node.IsScalar() && node.Scalar() == "defaults") return l;
  if (!node.IsMap()) {
    in.ThrowValue(node, kp, "a mapping of limits (stroke_min: -0.15, ...) or `defaults`");
  }
  in.CheckKeys(node, kp, {"stroke_min", "stroke_max", "max_increment", "force_soft",
                          "force_hard", "timeout", "initial_stiffness"});
  l.stroke_min = in.ReadNumber(node, kp, "stroke_min", "the lowest actuator position in m",
                               l.stroke_min);
  l.stroke_max = in.ReadNumber(node, kp, "stroke_max", "the highest actuator position in m",
                               l.stroke_max);
  l.max_increment = in.ReadNumber(node, kp, "max_increment",
                                  "the largest command step per stage in m", l.max_increment);
  l.force_soft = in.ReadNumber(node, kp, "force_soft", "the predicted-force limit in N",
                               l.force_soft);
  l.force_hard = in.ReadNumber(node, kp, "force_hard", "the measured-force limit in N",
                               l.force_hard);
  l.timeout = in.ReadNumber(node, kp, "timeout", "the longest wait for a measurement in s",
                            l.timeout);
  try {
    transfer::SafetyMonitor check(l);  // rejects inconsistent limits, naming the field
  } catch (const ConfigError& e) {
    throw ConfigError(fmt::format("{}: {}", in.Where(node, kp), e.what()));
  }
  return l;
}

// `initial_stiffness:` of a physical slot: K0 = dr/dd [N/m], `measure`, or
// {measure: true, amplitude: 0.001}.
void ParseInitialStiffness(const YamlInput& in, const YAML::Node& node, const std::string& kp,
                           substructures::PhysicalSpec& physical) {
  const std::string key = kp + ".initial_stiffness";
  const char* expected = "K0 in N/m (a positive number), `measure`, or {measure: true, amplitude: "
                         "0.001} (ramp amplitude in m)";
  if (node.IsScalar() && node.Scalar() == "measure") {
    physical.stiffness_ramp = 1e-3;
    return;
  }
  if (node.IsMap()) {
    in.CheckKeys(node, key, {"measure", "amplitude"});
    if (!node["measure"] || !node["measure"].IsScalar() || node["measure"].Scalar() != "true") {
      throw ConfigError(fmt::format("{}: expected {}", in.Where(node, key), expected));
    }
    physical.stiffness_ramp =
        node["amplitude"] ? in.PositiveNumber(node["amplitude"], key + ".amplitude",
                                              "the ramp amplitude in m (e.g. 0.001)")
                          : 1e-3;
    return;
  }
  physical.initial_stiffness = in.PositiveNumber(node, key, expected);
}

}  // namespace hybridtest::io::internal
