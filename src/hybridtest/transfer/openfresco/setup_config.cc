// See setup_config.h.
#include "hybridtest/transfer/openfresco/setup_config.h"

#include <fmt/core.h>

#include "hybridtest/common/error.h"
#include "hybridtest/common/yaml_input.h"

namespace hybridtest::transfer::openfresco {

ExpSetup ParseSetup(const YAML::Node& node, std::string_view where,
                    const EmulatedBenchConfig& bench) {
  const YamlInput in = YamlInput::ForNode(node);
  in.RequireMapping(node, where);
  in.CheckKeys(node, where, {"units", "transform", "initial_stiffness"});
  ExpSetup s;
  if (node["units"]) s.wire_units = ParseBenchUnits(node["units"], JoinKeyPath(where, "units"));
  // transform: exactly one row (one actuator) of n numbers.
  const std::string tp = JoinKeyPath(where, "transform");
  const YAML::Node t = node["transform"];
  constexpr std::string_view kExpected =
      "one row of n numbers, e.g. [[0.6, -0.8, -0.6, 0.8]] (one actuator, n element dofs)";
  if (!t || !t.IsSequence() || t.size() != 1 || !t[0].IsSequence() || t[0].size() == 0) {
    in.ThrowValue(t, tp, kExpected);
  }
  s.transform = in.Numbers(t[0], tp + "[0]", kExpected);
  s.p0 = bench.p0;
  s.initial_stiffness = bench.specimen ? bench.specimen->initial_stiffness() : 0.0;
  s.initial_stiffness = in.ReadNumber(node, where, "initial_stiffness",
                                      "the specimen's initial stiffness in N/m (>= 0)",
                                      s.initial_stiffness);
  try {
    ValidateSetup(s);
  } catch (const ConfigError& e) {
    throw ConfigError(fmt::format("{}: {}", where, e.what()));
  }
  return s;
}

ExpSetup LoadSetup(const std::string& path, const EmulatedBenchConfig& bench) {
  const YamlInput file = YamlInput::FromFile(path, "a 'bench:' mapping and an 'openfresco:' one");
  const YAML::Node top = file.root()["openfresco"];
  const YAML::Node b = file.root()["bench"];
  const YAML::Node inner =
      b && b.IsMap() ? b["openfresco"] : YAML::Node(YAML::NodeType::Undefined);
  if (top && inner) {
    throw ConfigError(fmt::format("{}: 'openfresco:' is given twice (at the top level and in "
                                  "'bench:'); keep one", path));
  }
  if (!top && !inner) {
    throw ConfigError(fmt::format(
        "{}: no 'openfresco:' section; --protocol openfresco needs one with `units:` and "
        "`transform: [[t1, ..., tn]]` (see examples/rotor/bench-openfresco.yaml)", path));
  }
  return top ? ParseSetup(top, fmt::format("{}: openfresco", path), bench)
             : ParseSetup(inner, fmt::format("{}: bench.openfresco", path), bench);
}

}  // namespace hybridtest::transfer::openfresco
