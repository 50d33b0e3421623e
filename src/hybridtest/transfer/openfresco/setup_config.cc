// See setup_config.h.
#include "hybridtest/transfer/openfresco/setup_config.h"

#include <fmt/core.h>

#include <utility>

#include "hybridtest/common/error.h"
#include "hybridtest/common/yaml_input.h"
#include "hybridtest/transfer/bench_spec.h"

namespace hybridtest::transfer::openfresco {

ExpSetup ParseSetup(const YAML::Node& node, std::string_view where_view,
                    const EmulatedBenchSpec& bench) {
  const std::string where(where_view);
  const YamlInput in = YamlInput::ForNode(node);
  in.RequireMapping(node, where);
  in.CheckKeys(node, where, {"units", "transform", "initial_stiffness"});
  const auto na = bench.actuators.size();
  ExpSetup s;
  s.actuators = static_cast<int>(na);
  if (node["units"]) s.wire_units = ParseBenchUnits(node["units"], JoinKeyPath(where, "units"));
  const auto matrix = [&](const YAML::Node& m, const std::string& kp, std::size_t rows,
                          std::size_t cols, const std::string& expected) {
    if (!m || !m.IsSequence() || m.size() != rows) in.ThrowValue(m, kp, expected);
    std::vector<double> out;
    for (std::size_t i = 0; i < rows; ++i) {
      if (!m[i].IsSequence()) in.ThrowValue(m[i], fmt::format("{}[{}]", kp, i), expected);
      const auto row = in.Numbers(m[i], fmt::format("{}[{}]", kp, i), expected);
      if (row.empty() || (cols != 0 && row.size() != cols) ||
          (!out.empty() && row.size() != out.size() / i)) {
        in.ThrowValue(m[i], fmt::format("{}[{}]", kp, i), expected);
      }
      out.insert(out.end(), row.begin(), row.end());
    }
    return out;
  };
  // transform: one row (one actuator) of n numbers per actuator.
  s.transform = matrix(
      node["transform"], JoinKeyPath(where, "transform"), na, 0,
      na == 1 ? std::string("one row of n numbers, e.g. [[0.6, -0.8, -0.6, 0.8]] (one actuator, "
                            "n element dofs)")
              : fmt::format("{} rows (one per actuator of the bench) of n numbers each, e.g. "
                            "[[1, 0], [0, 1]] (n element dofs)", na));
  // p0 is each actuator's own; K_a the specimen's unless given.
  for (const auto& a : bench.actuators) s.p0s.push_back(a.p0);
  const YAML::Node k = node["initial_stiffness"];
  const std::string kp = JoinKeyPath(where, "initial_stiffness");
  if (k && na == 1 && !k.IsSequence()) {  // one actuator: K0 as one number
    s.stiffness_matrix = {in.Number(k, kp, "the specimen's initial stiffness in N/m (>= 0)")};
  } else if (k) {
    s.stiffness_matrix = matrix(k, kp, na, na,
                                fmt::format("the specimen's initial stiffness in actuator "
                                            "coordinates, {} × {} in N/m", na, na));
  } else {
    for (std::size_t i = 0; i < na; ++i) {
      for (std::size_t j = 0; j < na; ++j) {
        s.stiffness_matrix.push_back(bench.stiffness(static_cast<Eigen::Index>(i),
                                                     static_cast<Eigen::Index>(j)));
      }
    }
  }
  try {
    ValidateSetup(s);
  } catch (const ConfigError& e) {
    throw ConfigError(fmt::format("{}: {}", where, e.what()));
  }
  return s;
}

namespace {

// The file's `openfresco:` section (at the top level or inside `bench:`) and its key path.
std::pair<YAML::Node, std::string> FindSection(const YamlInput& file, const std::string& path) {
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
        "`transform: [[t1, ..., tn]]`, one row per actuator (see "
        "examples/rotor/bench-openfresco.yaml, examples/06_blade_two_actuators/"
        "bench-2act-openfresco.yaml)", path));
  }
  return top ? std::pair{top, fmt::format("{}: openfresco", path)}
             : std::pair{inner, fmt::format("{}: bench.openfresco", path)};
}

}  // namespace

ExpSetup LoadSetup(const std::string& path, const EmulatedBenchSpec& bench) {
  const YamlInput file = YamlInput::FromFile(path, "a 'bench:' mapping and an 'openfresco:' one");
  const auto [node, where] = FindSection(file, path);
  return ParseSetup(node, where, bench);
}

}  // namespace hybridtest::transfer::openfresco
