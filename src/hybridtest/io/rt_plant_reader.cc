// See rt_plant_reader.h.
#include "hybridtest/io/rt_plant_reader.h"

#include <fmt/core.h>

#include <cmath>

#include "hybridtest/common/error.h"
#include "hybridtest/io/setup_config.h"
#include "hybridtest/transfer/delay_compensator.h"

namespace hybridtest::io {
namespace {

// Bounds of the keys that size a buffer or a loop of the emulated real-time plant and of the
// compensator (docs/real-time.md): the plant takes ceil(tick · rate_hz) RK4 substeps per tick,
// its delay line holds delay / tick commands and the ATS window window / tick samples, so an
// unbounded value (rate_hz: 1e12, window: 1e12) would hang the first tick or exhaust memory.
constexpr double kMinPlantRate = 1.0;      // Unit: [Hz]
constexpr double kMaxPlantRate = 1.0e6;    // Unit: [Hz]: 1,000 substeps per 1 ms tick
constexpr double kMaxPlantDelay = 1.0;     // Unit: [s]: actuator delays are milliseconds
constexpr double kMaxCompensatorWindow = 10.0;  // Unit: [s]

// parent[key] (or `fallback` when absent), a finite number in [min, max]; the message names
// the key and the range.
double BoundedNumber(const YamlInput& in, const YAML::Node& parent, const std::string& kp,
                     const std::string& key, const std::string& expected, double fallback,
                     double min, double max) {
  const double value = in.ReadNumber(parent, kp, key, expected, fallback);
  if (!(value >= min && value <= max)) {
    in.ThrowValue(parent[key], JoinKeyPath(kp, key),
                  fmt::format("{} from {:g} to {:g}", expected, min, max));
  }
  return value;
}

}  // namespace

namespace {

// parent[key] for n actuators: absent → `fallback` for each, a number → the same for each, a
// list → one per actuator (exactly n).
std::vector<double> PerActuator(const YamlInput& in, const YAML::Node& parent,
                                const std::string& kp, const std::string& key,
                                const std::string& expected, double fallback, int n) {
  const auto size = static_cast<std::size_t>(n);
  const YAML::Node node = parent[key];
  if (!node) return std::vector<double>(size, fallback);
  const std::string path = JoinKeyPath(kp, key);
  if (!node.IsSequence()) return std::vector<double>(size, in.Number(node, path, expected));
  std::vector<double> v = in.Numbers(node, path, expected);
  if (v.size() != size) {
    in.ThrowValue(node, path, fmt::format("{} numbers, one per actuator ({}), or one number for "
                                          "every actuator", n, expected));
  }
  return v;
}

// parent[key] as an n × n matrix (row-major), absent → 0: a number c (c on the diagonal), a
// list of n (the diagonal) or a list of n rows of n.
std::vector<double> ActuatorMatrix(const YamlInput& in, const YAML::Node& parent,
                                   const std::string& kp, const std::string& key,
                                   const std::string& expected, int n) {
  const auto size = static_cast<std::size_t>(n);
  std::vector<double> m(size * size, 0.0);
  const YAML::Node node = parent[key];
  if (!node) return m;
  const std::string path = JoinKeyPath(kp, key);
  const std::string shape =
      fmt::format("{}: a number (every actuator), a list of {} (the diagonal) or {} rows of {} "
                  "(actuator coordinates)", expected, n, n, n);
  if (node.IsSequence() && node.size() > 0 && node[0].IsSequence()) {
    const Eigen::MatrixXd read = ReadMatrix(in, node, path, shape.c_str());
    if (read.rows() != n || read.cols() != n) in.ThrowValue(node, path, shape);
    for (std::size_t i = 0; i < size; ++i) {
      for (std::size_t j = 0; j < size; ++j) {
        m[i * size + j] = read(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
      }
    }
    return m;
  }
  const std::vector<double> diagonal = PerActuator(in, parent, kp, key, shape, 0.0, n);
  for (std::size_t i = 0; i < size; ++i) m[i * size + i] = diagonal[i];
  return m;
}

transfer::ServoHydraulicConstants ReadServo(const YamlInput& in, const YAML::Node& k,
                                            const std::string& kkp,
                                            transfer::ServoHydraulicConstants v) {
  in.RequireMapping(k, kkp);
  in.CheckKeys(k, kkp, {"a1_beta0", "a2", "beta1", "beta2", "a3", "gain"});
  v.a1_beta0 = in.ReadNumber(k, kkp, "a1_beta0", "a number", v.a1_beta0);
  v.a2 = in.ReadNumber(k, kkp, "a2", "a number", v.a2);
  v.beta1 = in.ReadNumber(k, kkp, "beta1", "a number", v.beta1);
  v.beta2 = in.ReadNumber(k, kkp, "beta2", "a number", v.beta2);
  v.a3 = in.ReadNumber(k, kkp, "a3", "a number", v.a3);
  v.gain = in.ReadNumber(k, kkp, "gain", "a number", v.gain);
  return v;
}

}  // namespace

transfer::RtPlantConfig ReadRtPlantConfig(const TransferReadContext& c) {
  const YamlInput& in = c.in;
  in.CheckKeys(c.node, c.kp, {"type", "plant", "actuators", "delay", "lag", "rate_hz", "p0",
                              "specimen", "servo"});
  transfer::RtPlantConfig p;
  const std::string plant = in.ReadString(c.node, c.kp, "plant", "ideal");
  if (plant == "ideal") {
    p.kind = transfer::PlantKind::kIdeal;
  } else if (plant == "electromechanical") {
    p.kind = transfer::PlantKind::kElectromechanical;
  } else if (plant == "servo_hydraulic") {
    p.kind = transfer::PlantKind::kServoHydraulic;
  } else {
    in.ThrowValue(c.node["plant"], c.kp + ".plant", "ideal, electromechanical or servo_hydraulic");
  }
  const int n = c.node["actuators"]
                    ? static_cast<int>(in.Count(c.node["actuators"], c.kp + ".actuators",
                                                "the number of actuators", 1, 64))
                    : 1;
  p.actuators.assign(static_cast<std::size_t>(n), {});
  const auto delay = PerActuator(in, c.node, c.kp, "delay", "a pure delay in s", 0.0, n);
  const auto lag = PerActuator(in, c.node, c.kp, "lag", "the lag's time constant in s", 0.0, n);
  const auto p0 = PerActuator(in, c.node, c.kp, "p0", "the zero-force position in m", 0.0, n);
  for (int i = 0; i < n; ++i) {
    const auto a = static_cast<std::size_t>(i);
    if (!(delay[a] >= 0.0 && delay[a] <= kMaxPlantDelay)) {
      in.ThrowValue(c.node["delay"], JoinKeyPath(c.kp, "delay"),
                    fmt::format("a pure delay in s from 0 to {:g}", kMaxPlantDelay));
    }
    p.actuators[a].delay = delay[a];
    p.actuators[a].lag = lag[a];
    p.actuators[a].p0 = p0[a];
  }
  p.rate_hz = BoundedNumber(in, c.node, c.kp, "rate_hz", "the plant's integration rate in Hz",
                            4096.0, kMinPlantRate, kMaxPlantRate);
  const std::string skp = c.kp + ".specimen";
  const YAML::Node s = in.Mapping(c.node, "specimen", skp, true);
  in.CheckKeys(s, skp, {"mass", "stiffness", "damping", "zeta", "damping_exponent"});
  auto& law = p.specimen;
  law.mass = PerActuator(in, s, skp, "mass", "the mass moved by the actuator in kg", 0.0, n);
  law.stiffness = ActuatorMatrix(in, s, skp, "stiffness", "the specimen's stiffness in N/m", n);
  law.damping_exponent =
      in.ReadNumber(s, skp, "damping_exponent", "the damper's exponent α > 0", 1.0);
  if (s["zeta"] && s["damping"]) {
    throw ConfigError(fmt::format("{}: give `zeta` (a damping ratio) or `damping` (c), not both",
                                  in.Where(s, skp)));
  }
  if (s["zeta"]) {
    // c_ii = 2 ζ_i √(K_ii m_i): each actuator's own mode, the specimen's coupling undamped.
    const auto zeta = PerActuator(in, s, skp, "zeta", "a damping ratio ≥ 0", 0.0, n);
    law.damping.assign(law.stiffness.size(), 0.0);
    for (std::size_t i = 0; i < zeta.size(); ++i) {
      const double k = law.stiffness[i * zeta.size() + i];
      law.damping[i * zeta.size() + i] = 2.0 * zeta[i] * std::sqrt(std::max(0.0, k * law.mass[i]));
    }
  } else {
    law.damping = ActuatorMatrix(in, s, skp, "damping", "c in N·(s/m)^α", n);
  }
  if (const YAML::Node k = c.node["servo"]) {
    // One mapping for every actuator, or a list of one per actuator.
    const std::string kkp = c.kp + ".servo";
    if (k.IsSequence()) {
      if (k.size() != static_cast<std::size_t>(n)) {
        in.ThrowValue(k, kkp, fmt::format("one mapping of servo constants, or a list of {} (one "
                                          "per actuator)", n));
      }
      for (std::size_t i = 0; i < k.size(); ++i) {
        p.actuators[i].servo = ReadServo(in, k[i], fmt::format("{}[{}]", kkp, i), {});
      }
    } else {
      const auto v = ReadServo(in, k, kkp, {});
      for (auto& a : p.actuators) a.servo = v;
    }
  }
  transfer::ValidateRtPlantConfig(p, in.Where(c.node, c.kp));
  return p;
}

substructures::TransferSpec ReadRtPlant(const TransferReadContext& c) {
  const transfer::RtPlantConfig p = ReadRtPlantConfig(c);
  return {"rt_plant", [p] { return std::make_unique<transfer::RtPlant>(p); }};
}

substructures::TransferSpec ReadCompensated(const TransferReadContext& c) {
  const YamlInput& in = c.in;
  in.CheckKeys(c.node, c.kp, {"type", "method", "delay", "order", "window", "update_every",
                              "threshold", "bounds", "rate_limits", "inner", "spacing"});
  transfer::CompensatorConfig k;
  const std::string method = in.ReadString(c.node, c.kp, "method", "ats");
  if (method == "ats") {
    k.method = transfer::CompensationMethod::kAts;
  } else if (method == "polynomial") {
    k.method = transfer::CompensationMethod::kPolynomial;
  } else {
    in.ThrowValue(c.node["method"], c.kp + ".method", "ats or polynomial");
  }
  k.delay = BoundedNumber(in, c.node, c.kp, "delay", "the actuator's delay in s", k.delay, 0.0,
                          kMaxPlantDelay);
  if (c.node["order"]) {
    k.order = static_cast<int>(in.Count(c.node["order"], c.kp + ".order",
                                        "a polynomial order 1..4", 1, 4));
  }
  if (c.node["spacing"]) {
    k.spacing = static_cast<int>(in.Count(c.node["spacing"], c.kp + ".spacing",
                                          "ticks between the polynomial's nodes (0: automatic)",
                                          0, 100000));
  }
  k.window = BoundedNumber(in, c.node, c.kp, "window", "the ATS window in s", k.window, 1e-6,
                           kMaxCompensatorWindow);
  if (c.node["update_every"]) {
    k.update_every = static_cast<int>(in.Count(c.node["update_every"], c.kp + ".update_every",
                                               "ticks between ATS updates", 1, 1000000));
  }
  k.threshold = in.ReadNumber(c.node, c.kp, "threshold", "the smallest amplitude in m",
                              k.threshold);
  if (const YAML::Node b = c.node["bounds"]) {
    const std::string bkp = c.kp + ".bounds";
    in.RequireMapping(b, bkp);
    in.CheckKeys(b, bkp, {"a0", "a1", "a2"});
    const char* names[] = {"a0", "a1", "a2"};
    for (std::size_t i = 0; i < 3; ++i) {
      if (!b[names[i]]) continue;
      const auto v = in.Numbers(b[names[i]], bkp + "." + names[i], "[lower, upper]");
      if (v.size() != 2) in.ThrowValue(b[names[i]], bkp + "." + names[i], "[lower, upper]");
      k.lower[i] = v[0];
      k.upper[i] = v[1];
    }
  }
  if (c.node["rate_limits"]) {
    const auto v = in.Numbers(c.node["rate_limits"], c.kp + ".rate_limits",
                              "[a0 per s, a1 per s, a2 per s], e.g. [2, 0.05, 0.001]");
    if (v.size() != 3) {
      in.ThrowValue(c.node["rate_limits"], c.kp + ".rate_limits", "three rate limits");
    }
    k.rate_limit = {v[0], v[1], v[2]};
  }
  transfer::ValidateCompensatorConfig(k, in.Where(c.node, c.kp));
  if (!c.node["inner"] || !c.node["inner"].IsMap()) {
    throw ConfigError(fmt::format("{}: a compensated transfer needs `inner:`, the transfer it "
                                  "wraps (e.g. {{type: rt_plant, ...}})", in.Where(c.node, c.kp)));
  }
  const std::string ikp = c.kp + ".inner";
  TransferReadContext inner_context{in, c.node["inner"], ikp, c.bench_address, c.reply_timeout,
                                    c.limits, c.files_read};
  substructures::TransferSpec inner = ReadTransfer(inner_context);
  auto make = inner.make;
  // The type names what it wraps ("compensated rt_plant"): a campaign runs only in-process
  // benches, the monitor shows the bench.
  return {"compensated " + inner.type, [make, k] {
            return std::make_unique<transfer::DelayCompensator>(make(), k);
          }};
}

}  // namespace hybridtest::io
