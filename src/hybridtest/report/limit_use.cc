#include "hybridtest/report/limit_use.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>

#include "hybridtest/io/journal.h"
#include "hybridtest/report/json_text.h"

namespace hybridtest::report {
namespace {

using nlohmann::json;

// A limit of actuator k (−1: the only one): a number applies to every actuator, a list holds
// one per actuator.
void ReadJsonLimit(const json& object, const char* key, int k, double& value) {
  if (!object.contains(key)) return;
  const json& v = object[key];
  if (v.is_number()) value = v.get<double>();
  if (v.is_array() && k >= 0 && static_cast<std::size_t>(k) < v.size() && v[k].is_number()) {
    value = v[static_cast<std::size_t>(k)].get<double>();
  }
}

void ReadYamlLimit(const YAML::Node& node, const char* key, int k, double& value) {
  const YAML::Node v = node[key];
  if (!v) return;
  try {
    if (v.IsScalar()) value = v.as<double>();
    if (v.IsSequence() && k >= 0 && static_cast<std::size_t>(k) < v.size()) {
      value = v[static_cast<std::size_t>(k)].as<double>();
    }
  } catch (const YAML::Exception&) {
    // The run validated its config; a value that does not read back keeps the default.
  }
}

// The `safety` block of substructure `key` in the config text the run recorded; null if none.
YAML::Node ConfigSafety(const json& meta, const std::string& key) {
  if (!meta.is_object() || !meta.contains("config") || !meta["config"].is_string()) return {};
  try {
    const YAML::Node root = YAML::Load(meta["config"].get<std::string>());
    return YAML::Clone(root["substructures"][key]["safety"]);
  } catch (const YAML::Exception&) {
    return {};
  }
}

// One use series over the finite samples of `value`, divided by `limit`.
LimitUse MakeUse(const std::string& limit, const std::string& measure, double limit_value,
                 const Eigen::VectorXd& t, const Eigen::VectorXd& value) {
  LimitUse use{limit, measure, limit_value, {}, {}, 0, 0};
  std::vector<double> ts, us;
  for (Eigen::Index i = 0; i < t.size() && i < value.size(); ++i) {
    if (!std::isfinite(value[i]) || !std::isfinite(t[i])) continue;
    ts.push_back(t[i]);
    us.push_back(std::abs(value[i]) / limit_value);
    if (us.back() > use.peak) {
      use.peak = us.back();
      use.peak_t = t[i];
    }
  }
  use.t = Eigen::Map<Eigen::VectorXd>(ts.data(), static_cast<Eigen::Index>(ts.size()));
  use.use = Eigen::Map<Eigen::VectorXd>(us.data(), static_cast<Eigen::Index>(us.size()));
  return use;
}

// Time and command of every exchange: the stage record's when it exists, else the journal's.
std::pair<Eigen::VectorXd, Eigen::VectorXd> Exchanges(const io::RunData& run,
                                                      const PhysicalChannels& slot, bool& staged) {
  staged = false;
  const std::string stages_path = io::StagesPath(run.csv_path);
  std::error_code error;
  if (std::filesystem::is_regular_file(stages_path, error)) {
    try {
      const io::RunData stages = io::LoadRun(stages_path);
      if (stages.Has("t") && stages.Has(slot.command)) {
        staged = true;
        return {stages.Get("t"), stages.Get(slot.command)};
      }
    } catch (const Error&) {
      // An unreadable stage record: fall back to the journal.
    }
  }
  return {ChannelValues(run, "t"), ChannelValues(run, slot.command)};
}

}  // namespace

std::optional<transfer::SafetyLimits> FindSlotLimits(const io::RunData& run,
                                                     const std::string& slot) {
  return FindActuatorLimits(run, slot, -1);
}

std::optional<transfer::SafetyLimits> FindActuatorLimits(const io::RunData& run,
                                                         const std::string& substructure,
                                                         int actuator) {
  const json& meta = run.metadata;
  if (!meta.is_object()) return std::nullopt;
  transfer::SafetyLimits limits;
  const std::pair<const char*, double*> fields[] = {
      {"stroke_min", &limits.stroke_min}, {"stroke_max", &limits.stroke_max},
      {"max_increment", &limits.max_increment}, {"force_soft", &limits.force_soft},
      {"force_hard", &limits.force_hard}, {"timeout", &limits.timeout}};
  // The sidecar's own record of the limits.
  if (meta.contains("substructures") && meta["substructures"].is_array()) {
    for (const json& s : meta["substructures"]) {
      if (!s.is_object() || StringOr(s, "slot") != substructure || !s.contains("safety") ||
          !s["safety"].is_object()) {
        continue;
      }
      for (const auto& [key, field] : fields) ReadJsonLimit(s["safety"], key, actuator, *field);
      return limits;
    }
  }
  // The config text the run recorded.
  const YAML::Node safety = ConfigSafety(meta, substructure);
  if (!safety) return std::nullopt;
  if (safety.IsScalar() && safety.Scalar() == "defaults") return limits;
  if (!safety.IsMap()) return std::nullopt;
  for (const auto& [key, field] : fields) ReadYamlLimit(safety, key, actuator, *field);
  return limits;
}

std::optional<transfer::SafetyLimits> FindLimitsOf(const io::RunData& run,
                                                   const PhysicalChannels& channels) {
  return channels.actuator >= 0
             ? FindActuatorLimits(run, channels.substructure, channels.actuator)
             : FindSlotLimits(run, channels.slot);
}

std::vector<LimitUse> CalcLimitUse(const io::RunData& run, const PhysicalChannels& slot) {
  std::vector<LimitUse> uses;
  const auto limits = FindLimitsOf(run, slot);
  if (!limits) return uses;
  const Eigen::VectorXd t = ChannelValues(run, "t");
  if (!slot.command.empty()) {
    // Stroke: toward whichever end the command heads.
    const Eigen::VectorXd c = ChannelValues(run, slot.command);
    Eigen::VectorXd toward(c.size());
    for (Eigen::Index i = 0; i < c.size(); ++i) {
      const double up = limits->stroke_max > 0 ? c[i] / limits->stroke_max : 0;
      const double down = limits->stroke_min < 0 ? c[i] / limits->stroke_min : 0;
      toward[i] = std::isfinite(c[i]) ? std::max({up, down, 0.0}) : NAN;
    }
    uses.push_back(MakeUse("stroke", "command / stroke_max (stroke_min below 0)", 1.0, t,
                           toward));
    uses.back().limit_value = limits->stroke_max;
    // Increments between consecutive exchanges.
    bool staged = false;
    const auto [te, ce] = Exchanges(run, slot, staged);
    Eigen::VectorXd step = Eigen::VectorXd::Constant(ce.size(), NAN);
    double last = NAN;
    for (Eigen::Index i = 0; i < ce.size(); ++i) {
      if (!std::isfinite(ce[i])) continue;
      if (std::isfinite(last)) step[i] = ce[i] - last;
      last = ce[i];
    }
    uses.push_back(MakeUse("max_increment",
                           staged ? "|command increment| per stage"
                                  : "|command increment| between journal rows",
                           limits->max_increment, te, step));
  }
  if (!slot.force.empty()) {
    const Eigen::VectorXd f = ChannelValues(run, slot.force);
    uses.push_back(MakeUse("force_soft", "|measured force|", limits->force_soft, t, f));
    uses.push_back(MakeUse("force_hard", "|measured force|", limits->force_hard, t, f));
  }
  return uses;
}

std::vector<SlotLimitUse> CalcSlotLimitUse(const io::RunData& run, const RunLayout& layout,
                                           const std::string& substructure) {
  std::vector<SlotLimitUse> uses;
  const json& meta = run.metadata;
  if (!meta.is_object() || !meta.contains("substructures") || !meta["substructures"].is_array()) {
    return uses;
  }
  std::vector<std::string> slots;
  for (const json& s : meta["substructures"]) {
    if (!s.is_object() || StringOr(s, "slot") != substructure || !s.contains("slots") ||
        !s["slots"].is_array()) {
      continue;
    }
    for (const json& name : s["slots"]) {
      if (name.is_string()) slots.push_back(name.get<std::string>());
    }
  }
  const YAML::Node safety = ConfigSafety(meta, substructure);
  if (slots.empty() || !safety || !safety.IsMap() || !safety["slots"] ||
      !safety["slots"].IsMap()) {
    return uses;
  }
  const YAML::Node per_slot = safety["slots"];
  const Eigen::VectorXd t = ChannelValues(run, "t");
  for (std::size_t i = 0; i < slots.size(); ++i) {
    double max_displacement = NAN, max_force = NAN;
    ReadYamlLimit(per_slot, "max_displacement", static_cast<int>(i), max_displacement);
    ReadYamlLimit(per_slot, "max_force", static_cast<int>(i), max_force);
    const auto coordinate = layout.slot_coordinates.find(slots[i]);
    if (std::isfinite(max_displacement) && max_displacement > 0 &&
        coordinate != layout.slot_coordinates.end() && !coordinate->second.empty() &&
        FindChannel(run, coordinate->second) >= 0) {
      uses.push_back({slots[i], MakeUse("max_displacement", "|" + coordinate->second + "|",
                                        max_displacement, t,
                                        ChannelValues(run, coordinate->second))});
    }
    if (std::isfinite(max_force) && max_force > 0 && FindChannel(run, slots[i]) >= 0) {
      uses.push_back({slots[i], MakeUse("max_force", "|" + slots[i] + "|", max_force, t,
                                        ChannelValues(run, slots[i]))});
    }
  }
  return uses;
}

}  // namespace hybridtest::report
