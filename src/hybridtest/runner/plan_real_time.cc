// See plan_real_time.h.
#include "hybridtest/runner/plan_real_time.h"

#include <fmt/core.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "hybridtest/common/error.h"
#include "hybridtest/common/yaml_input.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/runner/delay_stability.h"
#include "hybridtest/runner/paced_loop.h"

namespace hybridtest::runner {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string TypeOf(const YAML::Node& n) {
  return n.IsMap() && n["type"] ? n["type"].as<std::string>() : std::string();
}

// The emulated plant under a transfer (itself, or a compensator's inner transfer).
YAML::Node PlantOf(const YAML::Node& transfer) {
  return TypeOf(transfer) == "compensated" ? transfer["inner"] : transfer;
}

// The physical slots of the config whose transfer is an emulated plant.
std::vector<std::string> PlantSlots(const YAML::Node& root, const std::string& path) {
  std::vector<std::string> slots;
  const YAML::Node subs = root["substructures"];
  if (subs.IsMap()) {
    for (const auto& kv : subs) {
      if (TypeOf(kv.second) != "physical") continue;
      if (TypeOf(PlantOf(kv.second["transfer"])) == "rt_plant") {
        slots.push_back(kv.first.as<std::string>());
      }
    }
  }
  if (slots.empty()) {
    throw ConfigError(fmt::format("{}: plan for a real-time run needs a physical slot on an "
                                  "emulated plant (transfer type rt_plant, or compensated around "
                                  "one); plan never moves a real bench", path));
  }
  return slots;
}

// The config with every plant slot behind `method` ("none", "polynomial", "ats"), starting
// from `delay[slot]`, at step dt, forced to run even if the stability check refuses it.
YAML::Node Variant(const YAML::Node& root, const std::vector<std::string>& slots,
                   const std::string& method, const std::map<std::string, double>& delay,
                   double dt) {
  YAML::Node v = YAML::Clone(root);
  v["integrator"]["dt"] = dt;
  v["real_time"]["force"] = true;
  for (const std::string& slot : slots) {
    YAML::Node sub = v["substructures"][slot];
    const YAML::Node transfer = sub["transfer"];
    const YAML::Node plant = YAML::Clone(PlantOf(transfer));
    if (method == "none") {
      sub["transfer"] = plant;
      continue;
    }
    const bool same = TypeOf(transfer) == "compensated" &&
                      (transfer["method"] ? transfer["method"].as<std::string>() : "ats") == method;
    if (same) continue;  // the configured compensator, its settings kept
    YAML::Node c;
    c["type"] = "compensated";
    c["method"] = method;
    // Shortest round-trip text, so that the printed YAML reads 0.0216, not 0.021600000000000001.
    c["delay"] = fmt::format("{}", delay.count(slot) ? delay.at(slot) : 0.0);
    if (method == "polynomial") c["order"] = 2;
    c["inner"] = plant;
    sub["transfer"] = c;
  }
  return v;
}

io::RunSpec Compile(const YAML::Node& config, const std::string& path) {
  YAML::Emitter out;
  out << config;
  io::RunSpec spec = io::CompileRunSpec(
      io::ParseSimulationConfig(YamlInput::FromText(out.c_str(), path)));
  spec.output.files = false;
  spec.quiet = true;
  return spec;
}

// Runs one candidate in virtual time; its margins go into `result`, the plant delays per slot
// into `plant_delay` (if given).
void RunCandidate(const YAML::Node& config, const std::string& path, RealTimePlanResult& result,
                  std::map<std::string, double>* plant_delay) {
  result.J1_ms = result.J2 = result.J3 = kNaN;
  try {
    io::RunSpec spec = Compile(config, path);
    spec.real_time.clock = "virtual";
    // The Session builds its pacer from the spec, as every run's (real_time.force: not
    // refused here, judged below).
    Session session(std::move(spec));
    const PacedLoop& loop = *session.paced_loop();
    result.critical_delay = std::numeric_limits<double>::infinity();
    for (const SlotDelayMargin& m : CheckDelayStability(session)) {
      result.critical_delay = std::min(result.critical_delay, m.critical_delay);
      result.remaining_delay = std::max(result.remaining_delay, m.remaining_delay);
      result.unstable = result.unstable || m.unstable();
      // The compensators start from it, to 0.1 ms.
      if (plant_delay != nullptr) (*plant_delay)[m.slot] = std::round(m.plant_delay * 1e4) / 1e4;
    }
    const StepResult r = session.Run();
    result.ok = r.status == SessionStatus::kFinished;
    result.failure = r.reason;
    result.J1_ms = loop.criteria().J1_ms();
    result.J2 = loop.criteria().J2();
    result.J3 = loop.criteria().J3();
    result.ticks = loop.statistics().ticks;
  } catch (const std::exception& e) {
    result.ok = false;
    result.failure = e.what();
  }
}

}  // namespace

std::string RealTimePlanResult::Label() const {
  return fmt::format("{}, dt {:.4g} ms", compensator, 1e3 * dt);
}

std::vector<RealTimePlanResult> PlanRealTime(const std::string& config_path,
                                             const RealTimePlanOptions& options) {
  const io::RunSpec configured = io::LoadRunSpec(config_path);
  if (!configured.real_time.enabled) {
    throw ConfigError(fmt::format("{}: no `real_time:` block: plan for real time plans a "
                                  "paced run (docs/real-time.md)", config_path));
  }
  const YAML::Node root = YamlInput::FromFile(config_path).root();
  const std::vector<std::string> slots = PlantSlots(root, config_path);
  std::vector<double> dts = options.dts;
  if (dts.empty()) dts = {configured.scheme.dt, 0.5 * configured.scheme.dt};
  const std::vector<std::string> methods = {"none", "polynomial", "ats"};
  const std::size_t count = dts.size() * methods.size();
  std::vector<RealTimePlanResult> results;
  for (double dt : dts) {
    // The plant alone first: its delay is where the compensators start.
    std::map<std::string, double> plant_delay;
    for (const std::string& method : methods) {
      RealTimePlanResult r;
      r.compensator = method;
      r.dt = dt;
      const YAML::Node v = Variant(root, slots, method, plant_delay, dt);
      RunCandidate(v, config_path, r, method == "none" ? &plant_delay : nullptr);
      if (method != "none") {
        const YAML::Node t = v["substructures"][slots.front()]["transfer"];
        r.compensation = t["delay"] ? t["delay"].as<double>() : 0.0;
      }
      results.push_back(r);
      if (options.on_result) options.on_result(results.size() - 1, count, results.back());
    }
  }
  return results;
}

std::optional<RealTimePlanResult> RecommendRealTime(
    const std::vector<RealTimePlanResult>& results) {
  std::optional<RealTimePlanResult> best;
  for (const RealTimePlanResult& r : results) {
    if (!r.ok || r.unstable || !std::isfinite(r.J2)) continue;
    if (!best || r.J2 < best->J2 || (r.J2 == best->J2 && r.dt > best->dt)) best = r;
  }
  return best;
}

std::string RealTimeCandidateYaml(const std::string& config_path,
                                  const RealTimePlanResult& result) {
  const YAML::Node root = YamlInput::FromFile(config_path).root();
  const std::vector<std::string> slots = PlantSlots(root, config_path);
  const std::map<std::string, double> delay = {{slots.front(), result.compensation}};
  const YAML::Node v = Variant(root, {slots.front()}, result.compensator, delay, result.dt);
  YAML::Node out;
  out["integrator"]["dt"] = fmt::format("{}", result.dt);
  out["substructures"][slots.front()]["transfer"] = v["substructures"][slots.front()]["transfer"];
  YAML::Emitter e;
  e << out;
  return e.c_str();
}

}  // namespace hybridtest::runner
