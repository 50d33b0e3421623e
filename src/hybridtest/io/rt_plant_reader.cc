// See rt_plant_reader.h.
#include "hybridtest/io/rt_plant_reader.h"

#include <fmt/core.h>

#include <cmath>

#include "hybridtest/common/error.h"

namespace hybridtest::io {

transfer::RtPlantConfig ReadRtPlantConfig(const TransferReadContext& c) {
  const YamlInput& in = c.in;
  in.CheckKeys(c.node, c.kp, {"type", "plant", "delay", "lag", "rate_hz", "p0", "specimen",
                              "servo"});
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
  p.delay = in.ReadNumber(c.node, c.kp, "delay", "a pure delay ≥ 0 in s", 0.0);
  p.lag = in.ReadNumber(c.node, c.kp, "lag", "the lag's time constant in s", 0.0);
  p.rate_hz = in.ReadNumber(c.node, c.kp, "rate_hz", "the plant's rate in Hz", 4096.0);
  p.p0 = in.ReadNumber(c.node, c.kp, "p0", "the zero-force position in m", 0.0);
  const std::string skp = c.kp + ".specimen";
  const YAML::Node s = in.Mapping(c.node, "specimen", skp, true);
  in.CheckKeys(s, skp, {"mass", "stiffness", "damping", "zeta", "damping_exponent"});
  auto& law = p.specimen;
  law.mass = in.ReadNumber(s, skp, "mass", "the specimen's mass in kg", 0.0);
  law.stiffness = in.ReadNumber(s, skp, "stiffness", "the specimen's stiffness in N/m", 0.0);
  law.damping_exponent =
      in.ReadNumber(s, skp, "damping_exponent", "the damper's exponent α > 0", 1.0);
  if (s["zeta"] && s["damping"]) {
    throw ConfigError(fmt::format("{}: give `zeta` (a damping ratio) or `damping` (c), not both",
                                  in.Where(s, skp)));
  }
  if (s["zeta"]) {
    const double zeta = in.Number(s["zeta"], skp + ".zeta", "a damping ratio ≥ 0");
    law.damping = 2.0 * zeta * std::sqrt(std::max(0.0, law.stiffness * law.mass));
  } else {
    law.damping = in.ReadNumber(s, skp, "damping", "c in N·(s/m)^α", 0.0);
  }
  if (const YAML::Node k = c.node["servo"]) {
    const std::string kkp = c.kp + ".servo";
    in.RequireMapping(k, kkp);
    in.CheckKeys(k, kkp, {"a1_beta0", "a2", "beta1", "beta2", "a3", "gain"});
    auto& v = p.servo;
    v.a1_beta0 = in.ReadNumber(k, kkp, "a1_beta0", "a number", v.a1_beta0);
    v.a2 = in.ReadNumber(k, kkp, "a2", "a number", v.a2);
    v.beta1 = in.ReadNumber(k, kkp, "beta1", "a number", v.beta1);
    v.beta2 = in.ReadNumber(k, kkp, "beta2", "a number", v.beta2);
    v.a3 = in.ReadNumber(k, kkp, "a3", "a number", v.a3);
    v.gain = in.ReadNumber(k, kkp, "gain", "a number", v.gain);
  }
  transfer::ValidateRtPlantConfig(p, in.Where(c.node, c.kp));
  return p;
}

substructures::TransferSpec ReadRtPlant(const TransferReadContext& c) {
  const transfer::RtPlantConfig p = ReadRtPlantConfig(c);
  return {"rt_plant", [p] { return std::make_unique<transfer::RtPlant>(p); }};
}

}  // namespace hybridtest::io
