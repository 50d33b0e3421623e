// See resume_changes.h.
#include "hybridtest/runner/resume_changes.h"

#include <fmt/core.h>

#include <charconv>
#include <cmath>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/safety.h"

namespace hybridtest::runner {
namespace {

constexpr const char* kAccepted =
    "substructures.SLOT.safety.{stroke_min,stroke_max,max_increment,force_soft,force_hard,"
    "timeout} or resume.{force_tolerance,position_tolerance}";

double ParseValue(const std::string& setting, const std::string& text) {
  double value = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value)) {
    throw ConfigError(fmt::format("--set {}: '{}' is not a finite number; give the value in SI "
                                  "units (m, N, s), e.g. --set substructures.r1.safety."
                                  "force_soft=9000", setting, text));
  }
  return value;
}

double* SafetyField(transfer::SafetyLimits& l, const std::string& name) {
  if (name == "stroke_min") return &l.stroke_min;
  if (name == "stroke_max") return &l.stroke_max;
  if (name == "max_increment") return &l.max_increment;
  if (name == "force_soft") return &l.force_soft;
  if (name == "force_hard") return &l.force_hard;
  if (name == "timeout") return &l.timeout;
  return nullptr;
}

}  // namespace

nlohmann::json ApplyResumeChanges(io::RunSpec& spec, const std::vector<std::string>& settings) {
  nlohmann::json changes = nlohmann::json::array();
  for (const std::string& setting : settings) {
    const auto eq = setting.find('=');
    if (eq == std::string::npos) {
      throw ConfigError(fmt::format("--set {}: expected KEY=VALUE with KEY one of {}", setting,
                                    kAccepted));
    }
    const std::string key = setting.substr(0, eq);
    const double value = ParseValue(setting, setting.substr(eq + 1));
    nlohmann::json from;
    if (key == "resume.force_tolerance" || key == "resume.position_tolerance") {
      if (!(value > 0.0)) {
        throw ConfigError(fmt::format("--set {}: expected a positive tolerance", setting));
      }
      auto& field = key == "resume.force_tolerance" ? spec.resume.force_tolerance
                                                    : spec.resume.position_tolerance;
      from = field ? nlohmann::json(*field) : nlohmann::json(nullptr);
      field = value;
    } else {
      const std::string prefix = "substructures.";
      const auto safety = key.find(".safety.");
      if (key.rfind(prefix, 0) != 0 || safety == std::string::npos) {
        throw ConfigError(fmt::format("--set {}: unknown key '{}'; expected {}", setting, key,
                                      kAccepted));
      }
      const std::string slot = key.substr(prefix.size(), safety - prefix.size());
      const std::string name = key.substr(safety + 8);
      substructures::SubstructureSpec* sub = nullptr;
      for (auto& s : spec.substructures) {
        if (s.slot == slot) sub = &s;
      }
      if (sub == nullptr || !sub->physical) {
        throw ConfigError(fmt::format("--set {}: slot '{}' is not a physical slot of this run; "
                                      "safety limits belong to physical slots", setting, slot));
      }
      transfer::SafetyLimits limits = sub->physical->limits;
      double* field = SafetyField(limits, name);
      if (field == nullptr) {
        throw ConfigError(fmt::format("--set {}: unknown safety limit '{}'; expected {}",
                                      setting, name, kAccepted));
      }
      from = *field;
      *field = value;
      try {
        transfer::SafetyMonitor check(limits);  // names the inconsistent field
      } catch (const ConfigError& e) {
        throw ConfigError(fmt::format("--set {}: {}", setting, e.what()));
      }
      sub->physical->limits = limits;
    }
    changes.push_back({{"key", key}, {"from", from}, {"to", value}});
  }
  return changes;
}

}  // namespace hybridtest::runner
