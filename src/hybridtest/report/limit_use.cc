#include "hybridtest/report/limit_use.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>

#include "hybridtest/io/journal.h"

namespace hybridtest::report {
namespace {

using nlohmann::json;

void ReadJsonLimit(const json& object, const char* key, double& value) {
  if (object.contains(key) && object[key].is_number()) value = object[key].get<double>();
}

void ReadYamlLimit(const YAML::Node& node, const char* key, double& value) {
  if (!node[key] || !node[key].IsScalar()) return;
  try {
    value = node[key].as<double>();
  } catch (const YAML::Exception&) {
    // The run validated its config; a value that does not read back keeps the default.
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
  const json& meta = run.metadata;
  if (!meta.is_object()) return std::nullopt;
  transfer::SafetyLimits limits;
  // The sidecar's own record of the limits.
  if (meta.contains("substructures") && meta["substructures"].is_array()) {
    for (const json& s : meta["substructures"]) {
      if (!s.is_object() || s.value("slot", "") != slot || !s.contains("safety") ||
          !s["safety"].is_object()) {
        continue;
      }
      const std::pair<const char*, double*> fields[] = {
          {"stroke_min", &limits.stroke_min}, {"stroke_max", &limits.stroke_max},
          {"max_increment", &limits.max_increment}, {"force_soft", &limits.force_soft},
          {"force_hard", &limits.force_hard}, {"timeout", &limits.timeout}};
      for (const auto& [key, field] : fields) ReadJsonLimit(s["safety"], key, *field);
      return limits;
    }
  }
  // The config text the run recorded.
  if (!meta.contains("config") || !meta["config"].is_string()) return std::nullopt;
  try {
    const YAML::Node root = YAML::Load(meta["config"].get<std::string>());
    const YAML::Node safety = root["substructures"][slot]["safety"];
    if (!safety) return std::nullopt;
    if (safety.IsScalar() && safety.Scalar() == "defaults") return limits;
    if (!safety.IsMap()) return std::nullopt;
    ReadYamlLimit(safety, "stroke_min", limits.stroke_min);
    ReadYamlLimit(safety, "stroke_max", limits.stroke_max);
    ReadYamlLimit(safety, "max_increment", limits.max_increment);
    ReadYamlLimit(safety, "force_soft", limits.force_soft);
    ReadYamlLimit(safety, "force_hard", limits.force_hard);
    ReadYamlLimit(safety, "timeout", limits.timeout);
    return limits;
  } catch (const YAML::Exception&) {
    return std::nullopt;
  }
}

std::vector<LimitUse> CalcLimitUse(const io::RunData& run, const PhysicalChannels& slot) {
  std::vector<LimitUse> uses;
  const auto limits = FindSlotLimits(run, slot.slot);
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

}  // namespace hybridtest::report
