// See setup_config.h.
#include "hybridtest/io/setup_config.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "hybridtest/common/error.h"

namespace hybridtest::io {
namespace {

// A list of `count` points or directions of `dim` coordinates (dim 0: 2 or 3, set by the first).
Eigen::VectorXd ReadPoint(const YamlInput& in, const YAML::Node& node, const std::string& kp,
                          int& dim, const char* expected) {
  const auto values = in.Numbers(node, kp, expected);
  const int size = static_cast<int>(values.size());
  if ((size != 2 && size != 3) || (dim != 0 && size != dim)) {
    throw ConfigError(fmt::format("{}: {} coordinates; expected {} ({})", in.Where(node, kp), size,
                                  dim == 0 ? "2 or 3" : std::to_string(dim), expected));
  }
  dim = size;
  return Eigen::Map<const Eigen::VectorXd>(values.data(), size);
}

Eigen::VectorXd PerSlot(const YamlInput& in, const YAML::Node& node, const std::string& kp, int m,
                        const char* expected) {
  if (node.IsScalar()) {
    return Eigen::VectorXd::Constant(m, in.PositiveNumber(node, kp, expected));
  }
  const auto values = in.Numbers(node, kp, expected);
  if (static_cast<int>(values.size()) != m) {
    throw ConfigError(fmt::format("{}: {} values; expected one per slot ({}) or one value for "
                                  "every slot: {}", in.Where(node, kp), values.size(), m,
                                  expected));
  }
  Eigen::VectorXd v(m);
  for (int i = 0; i < m; ++i) {
    if (!(values[static_cast<std::size_t>(i)] > 0.0)) {
      in.ThrowValue(node, kp, fmt::format("positive values: {}", expected));
    }
    v(i) = values[static_cast<std::size_t>(i)];
  }
  return v;
}

}  // namespace

// Actuator k's view of a `safety:` mapping of n actuators: a list gives one value per
// actuator (its length must be n), a scalar applies to every actuator.
YAML::Node PickActuator(const YamlInput& in, const YAML::Node& node, std::size_t k,
                        std::size_t n, const std::string& kp) {
  if (!node || !node.IsMap()) return node;
  YAML::Node out(YAML::NodeType::Map);
  for (const auto& kv : node) {
    const std::string key = kv.first.as<std::string>();
    if (kv.second.IsSequence() && kv.second.size() != n) {
      throw ConfigError(fmt::format("{}: a list of {} values; expected {} (one per actuator, a "
                                    "row of setup.transform or entry of setup.actuators) or one value for every actuator",
                                    in.Where(kv.second, kp + "." + key), kv.second.size(), n));
    }
    out[key] = kv.second.IsSequence() ? YAML::Clone(kv.second[k]) : YAML::Clone(kv.second);
  }
  return out;
}

Eigen::MatrixXd ReadMatrix(const YamlInput& in, const YAML::Node& node, const std::string& kp,
                           const char* expected) {
  if (!node.IsSequence() || node.size() == 0 || !node[0].IsSequence()) {
    in.ThrowValue(node, kp, expected);
  }
  Eigen::MatrixXd m(static_cast<Eigen::Index>(node.size()),
                    static_cast<Eigen::Index>(node[0].size()));
  for (std::size_t i = 0; i < node.size(); ++i) {
    const auto row = in.Numbers(node[i], fmt::format("{}[{}]", kp, i), expected);
    if (static_cast<Eigen::Index>(row.size()) != m.cols()) in.ThrowValue(node[i], kp, expected);
    for (std::size_t j = 0; j < row.size(); ++j) {
      m(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = row[j];
    }
  }
  return m;
}

substructures::LinearSetup ParseLinearSetup(const YamlInput& in, const YAML::Node& setup,
                                            const std::string& sp, int m) {
  const char* expected = "a mapping: {p0: [..], transform: [[..]]} (a − p0 = T d, T n_act × m) "
                         "or {geometry: large_displacement, p0: [..], directions: [..], "
                         "actuators: [..]}";
  if (!setup || !setup.IsMap()) in.ThrowValue(setup, sp, expected);
  if (!setup["transform"] || !setup["p0"]) {
    throw ConfigError(fmt::format("{}: a physical substructure of several slots needs `setup: "
                                  "{{p0: [..], transform: [[..]]}}` (a − p0 = T d, T n_act × m) "
                                  "or `setup: {{geometry: large_displacement, p0: [..], "
                                  "directions: [..], actuators: [..]}}`", in.Where(setup, sp)));
  }
  in.CheckKeys(setup, sp, {"geometry", "p0", "transform", "load_cell_zero"});
  substructures::LinearSetup linear;
  linear.transform = ReadMatrix(in, setup["transform"], sp + ".transform",
                                "a list of rows, one per actuator, one column per slot");
  const auto n = linear.transform.rows();
  auto vec = [&](const char* key, const char* what) {
    Eigen::VectorXd v = Eigen::VectorXd::Zero(n);
    if (!setup[key]) return v;
    const auto values = in.Numbers(setup[key], sp + "." + key, what);
    if (static_cast<Eigen::Index>(values.size()) != n) in.ThrowValue(setup[key], sp + "." + key, what);
    for (Eigen::Index k = 0; k < n; ++k) v(k) = values[static_cast<std::size_t>(k)];
    return v;
  };
  linear.p0 = vec("p0", "one actuator position at zero specimen force per actuator, in m");
  linear.load_cell_zero = vec("load_cell_zero", "one load-cell zero per actuator, in N");
  if (linear.transform.cols() != m) {
    throw ConfigError(fmt::format("{}: T has {} columns for the {} slots of `slots:`; give one "
                                  "column per slot", in.Where(setup["transform"], sp + ".transform"),
                                  linear.transform.cols(), m));
  }
  try {
    linear.Validate();
  } catch (const ConfigError& e) {
    throw ConfigError(fmt::format("{}: {}", in.Where(setup, sp), e.what()));
  }
  return linear;
}

bool IsLargeDisplacementSetup(const YamlInput& in, const YAML::Node& setup, const std::string& sp) {
  if (!setup || !setup.IsMap() || !setup["geometry"]) return false;
  const std::string g = in.String(setup["geometry"], sp + ".geometry",
                                  "linear or large_displacement");
  if (g == "large_displacement") return true;
  if (g == "linear") return false;
  in.ThrowValue(setup["geometry"], sp + ".geometry",
                "linear (a = p0 + T d, with transform:) or large_displacement (rods, with "
                "directions: and actuators:)");
}

std::shared_ptr<const substructures::RodSetup> ParseRodSetup(const YamlInput& in,
                                                             const YAML::Node& setup,
                                                             const std::string& sp, int m) {
  in.CheckKeys(setup, sp, {"geometry", "p0", "directions", "actuators", "load_cell_zero"});
  const YAML::Node dirs = setup["directions"], rods = setup["actuators"];
  if (!dirs || !dirs.IsSequence() || dirs.size() == 0) {
    in.ThrowValue(dirs, sp + ".directions",
                  "one direction [ex, ey, ez] (or [ex, ey]) per slot, in the order of `slots:`");
  }
  if (!rods || !rods.IsSequence() || rods.size() == 0) {
    in.ThrowValue(rods, sp + ".actuators",
                  "one {base: [x, y, z], attach: [x, y, z]} per actuator, in m");
  }
  if (static_cast<int>(dirs.size()) != m) {
    throw ConfigError(fmt::format("{}: {} directions for the {} slots of `slots:`; give one "
                                  "direction per slot", in.Where(dirs, sp + ".directions"),
                                  dirs.size(), m));
  }
  int dim = 0;
  substructures::RodGeometry g;
  const auto n = static_cast<Eigen::Index>(rods.size());
  Eigen::VectorXd axis;
  for (std::size_t i = 0; i < dirs.size(); ++i) {
    const std::string dp = fmt::format("{}.directions[{}]", sp, i);
    if (dirs[i].IsMap()) {  // the rotational slot: {rotation_about: [x, y(, z)], axis: [..]}
      in.CheckKeys(dirs[i], dp, {"rotation_about", "axis"});
      if (g.rotation_slot >= 0) {
        throw ConfigError(fmt::format("{}: a second rotational slot; at most one slot may turn "
                                      "the specimen", in.Where(dirs[i], dp)));
      }
      g.rotation_slot = static_cast<int>(i);
      g.rotation_point = ReadPoint(in, dirs[i]["rotation_about"], dp + ".rotation_about", dim,
                                   "a point on the rotation axis, in m");
      if (dirs[i]["axis"]) {
        axis = ReadPoint(in, dirs[i]["axis"], dp + ".axis", dim, "the rotation axis [ax, ay, az]");
      }
      if (dim == 3 && axis.size() == 0) {
        in.ThrowValue(dirs[i]["axis"], dp + ".axis", "the rotation axis [ax, ay, az] (3-D)");
      }
      if (dim == 2 && axis.size() != 0) {
        in.ThrowValue(dirs[i]["axis"], dp + ".axis",
                      "no axis in 2-D (the rotation is in the plane, about rotation_about)");
      }
      if (i == 0) g.directions = Eigen::MatrixXd::Zero(dim, m);
      continue;
    }
    const Eigen::VectorXd e = ReadPoint(in, dirs[i], dp, dim,
                                        "a direction in the setup's frame, [m/m], or "
                                        "{rotation_about: [x, y, z], axis: [ax, ay, az]}");
    if (i == 0) g.directions.resize(dim, m);
    g.directions.col(static_cast<Eigen::Index>(i)) = e;
  }
  g.rotation_axis = axis;
  g.bases.resize(dim, n);
  g.attachments.resize(dim, n);
  for (std::size_t k = 0; k < rods.size(); ++k) {
    const std::string rp = fmt::format("{}.actuators[{}]", sp, k);
    in.RequireMapping(rods[k], rp);
    in.CheckKeys(rods[k], rp, {"base", "attach"});
    g.bases.col(static_cast<Eigen::Index>(k)) =
        ReadPoint(in, rods[k]["base"], rp + ".base", dim, "the rod's fixed pin, [x, y, z] in m");
    g.attachments.col(static_cast<Eigen::Index>(k)) = ReadPoint(
        in, rods[k]["attach"], rp + ".attach", dim, "the rod's pin on the specimen at d = 0, in m");
  }
  auto vec = [&](const char* key, const char* what) {
    Eigen::VectorXd v = Eigen::VectorXd::Zero(n);
    if (!setup[key]) return v;
    const auto values = in.Numbers(setup[key], sp + "." + key, what);
    if (static_cast<Eigen::Index>(values.size()) != n) {
      throw ConfigError(fmt::format("{}: {} values for {} actuators (`actuators:`); expected {}",
                                    in.Where(setup[key], sp + "." + key), values.size(), n, what));
    }
    for (Eigen::Index k = 0; k < n; ++k) v(k) = values[static_cast<std::size_t>(k)];
    return v;
  };
  if (!setup["p0"]) {
    in.ThrowValue(setup["p0"], sp + ".p0",
                  "one actuator position at zero specimen force per actuator, in m");
  }
  g.p0 = vec("p0", "one actuator position at zero specimen force per actuator, in m");
  g.load_cell_zero = vec("load_cell_zero", "one load-cell zero per actuator, in N");
  try {
    return std::make_shared<const substructures::RodSetup>(std::move(g));
  } catch (const ConfigError& e) {
    throw ConfigError(fmt::format("{}: {}", in.Where(setup, sp), e.what()));
  }
}

YAML::Node WithoutSlotLimits(const YAML::Node& safety) {
  if (!safety || !safety.IsMap() || !safety["slots"]) return safety;
  YAML::Node out(YAML::NodeType::Map);
  for (const auto& kv : safety) {
    const std::string key = kv.first.as<std::string>();
    if (key != "slots") out[key] = YAML::Clone(kv.second);
  }
  return out;
}

std::optional<substructures::SlotLimits> ParseSlotLimits(const YamlInput& in,
                                                         const YAML::Node& safety,
                                                         const std::string& kp,
                                                         const std::vector<std::string>& names) {
  if (!safety || !safety.IsMap() || !safety["slots"]) return std::nullopt;
  const std::string sp = kp + ".slots";
  const YAML::Node node = safety["slots"];
  in.RequireMapping(node, sp);
  in.CheckKeys(node, sp, {"max_displacement", "max_force"});
  const int m = static_cast<int>(names.size());
  substructures::SlotLimits l;
  l.names = names;
  const double inf = std::numeric_limits<double>::infinity();
  l.max_displacement = node["max_displacement"]
                           ? PerSlot(in, node["max_displacement"], sp + ".max_displacement", m,
                                     "the largest slot displacement |d_i| in m")
                           : Eigen::VectorXd::Constant(m, inf);
  l.max_force = node["max_force"] ? PerSlot(in, node["max_force"], sp + ".max_force", m,
                                            "the largest slot restoring force |r_i| in N")
                                  : Eigen::VectorXd::Constant(m, inf);
  return l;
}

void CheckGeometryWithinStroke(const YamlInput& in, const YAML::Node& setup, const std::string& sp,
                               const substructures::RodSetup& geometry,
                               const std::vector<transfer::SafetyLimits>& limits,
                               const std::optional<substructures::SlotLimits>& slot_limits) {
  const int m = geometry.num_slots();
  double stroke = 0.0;  // the longest actuator travel from p0 [m]
  for (int k = 0; k < geometry.num_actuators(); ++k) {
    const auto& l = limits[static_cast<std::size_t>(k)];
    stroke = std::max({stroke, l.stroke_max - geometry.p0()(k), geometry.p0()(k) - l.stroke_min});
  }
  Eigen::VectorXd half(m);
  double arm = std::numeric_limits<double>::infinity();  // the shortest non-zero lever arm [m]
  for (int k = 0; k < geometry.num_actuators(); ++k) {
    if (geometry.lever_arm(k) > 0.0) arm = std::min(arm, geometry.lever_arm(k));
  }
  for (int i = 0; i < m; ++i) {
    half(i) = i == geometry.geometry().rotation_slot
                  ? std::min(std::acos(-1.0) / 2.0, stroke / arm)  // [rad]
                  : stroke / geometry.geometry().directions.col(i).norm();
    if (slot_limits && std::isfinite(slot_limits->max_displacement(i))) {
      half(i) = slot_limits->max_displacement(i);
    }
  }
  constexpr double kThreshold = 0.01;
  const auto p = substructures::FindNearSingular(geometry, half, limits, kThreshold);
  if (!p) return;
  std::string at;
  for (int i = 0; i < m; ++i) at += fmt::format("{}{:.4g}", i ? ", " : "", p->d(i));
  throw ConfigError(fmt::format(
      "{}: at slot displacements [{}] m, within every actuator's stroke, the rods' axes are "
      "nearly parallel in the slots' plane (J(d) has {:.2g} % of its smallest singular value at "
      "d = 0; a slot force would need 100 times the actuator forces): limit the slots "
      "(safety.slots.max_displacement, [m]) or the strokes, or move the rods' base points",
      in.Where(setup, sp), at, 100.0 * p->ratio));
}

}  // namespace hybridtest::io
