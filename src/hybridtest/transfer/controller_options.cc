// See controller_options.h.
#include "hybridtest/transfer/controller_options.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "hybridtest/common/error.h"

namespace hybridtest::transfer {
namespace {

// One limit for all actuators, or a list of one per actuator [bench length unit].
std::vector<double> ReadFollowingErrors(const YamlInput& in, const YAML::Node& f,
                                        const std::string& fkp, std::size_t actuators,
                                        const std::string& unit) {
  const std::string what = fmt::format(
      "the largest |command − measured position| after a move, in the bench length unit ({})",
      unit);
  if (!f.IsSequence()) return {in.PositiveNumber(f, fkp, what)};
  if (f.size() != actuators) {
    throw ConfigError(fmt::format("{}: {} values for {} actuator{}: give one limit per actuator, "
                                  "or one for all", in.Where(f, fkp), f.size(), actuators,
                                  actuators == 1 ? "" : "s"));
  }
  std::vector<double> out;
  for (std::size_t k = 0; k < f.size(); ++k) {
    out.push_back(in.PositiveNumber(f[k], fmt::format("{}[{}]", fkp, k), what));
  }
  return out;
}

bool PositiveFinite(double value) { return value > 0.0 && std::isfinite(value); }

}  // namespace

void ReadControllerOptions(const YamlInput& in, const YAML::Node& node, const std::string& kp,
                           double default_timeout, const SafetyLimits* limits,
                           const BenchUnits& units, std::size_t actuators, ControllerOptions& o) {
  const auto seconds = [&](const char* key, double fallback) {
    return node[key] ? in.PositiveNumber(node[key], kp + "." + key, "a time in seconds")
                     : fallback;
  };
  o.ack_timeout = seconds("timeout", default_timeout);
  o.response_timeout = seconds("response_timeout", std::min(o.response_timeout, o.ack_timeout));
  o.connect_timeout = seconds("connect_timeout", o.connect_timeout);
  o.hold_timeout = seconds("hold_timeout", o.hold_timeout);
  o.poll_interval = in.ReadNumber(node, kp, "poll_interval",
                                  "a pause in seconds (0: poll back to back)", o.poll_interval);
  if (o.poll_interval < 0.0) {
    in.ThrowValue(node["poll_interval"], kp + ".poll_interval", "a non-negative time in seconds");
  }
  const std::string& unit = units.length_name;
  if (const YAML::Node p = in.Mapping(node, "plausibility", kp + ".plausibility", false);
      p.IsDefined()) {
    const std::string pkp = kp + ".plausibility";
    in.CheckKeys(p, pkp, {"position_tolerance", "force"});
    if (p["position_tolerance"]) {
      o.position_tolerance = in.PositiveNumber(
          p["position_tolerance"], pkp + ".position_tolerance",
          fmt::format("the largest |position − command| of the first exchange, in the bench "
                      "length unit ({})", unit));
    }
    if (p["force"]) {
      o.force_plausible = in.PositiveNumber(
          p["force"], pkp + ".force",
          fmt::format("the largest |force| of the first exchange, in the bench force unit ({})",
                      units.force_name));
    }
  }
  // The in-position window and the following error, checked against the slot's limits.
  const SafetyLimits l = limits != nullptr ? *limits : SafetyLimits{};
  const double metres = units.metres_per_length_unit;
  o.settle_tolerance = InBenchUnit(kDefaultSettleTolerance, metres);
  if (const YAML::Node t = node["settle_tolerance"]; t.IsDefined()) {
    const std::string tkp = kp + ".settle_tolerance";
    o.settle_tolerance = in.PositiveNumber(
        t, tkp, fmt::format("the controller's settling (in-position) window, in the bench "
                            "length unit ({})", unit));
    if (*o.settle_tolerance * metres > l.max_increment) {
      throw ConfigError(fmt::format(
          "{}: {} {} is wider than the slot's safety.max_increment ({} {}): a controller that "
          "calls a move settled that far from its target has not settled; give the window in {} "
          "(the bench length unit), typically 0.01 to 0.1 mm", in.Where(t, tkp),
          *o.settle_tolerance, unit, l.max_increment / metres, unit, unit));
    }
  }
  if (const YAML::Node f = node["following_error"]; f.IsDefined()) {
    const std::string fkp = kp + ".following_error";
    const std::vector<double> errors = ReadFollowingErrors(in, f, fkp, actuators, unit);
    for (double limit : errors) {
      if (limit * metres > l.stroke_max - l.stroke_min) {
        throw ConfigError(fmt::format(
            "{}: {} {} is longer than the whole stroke ({} m to {} m), so it could never stop "
            "anything: give it in {} (the bench length unit), e.g. the slot's max_increment "
            "{} {}", in.Where(f, fkp), limit, unit, l.stroke_min, l.stroke_max, unit,
            l.max_increment / metres, unit));
      }
    }
    o.following_error = errors[0];
    if (errors.size() > 1) o.following_errors = errors;
  } else {
    o.following_error =
        DefaultFollowingError(*o.settle_tolerance, InBenchUnit(l.max_increment, metres));
  }
}

std::vector<SettledReadingCheck::Limits> ResolveControllerOptions(ControllerOptions& o,
                                                                  const BenchUnits& units,
                                                                  std::size_t actuators,
                                                                  std::string_view who) {
  for (const auto& [name, value] :
       {std::pair{"connect_timeout", o.connect_timeout}, {"response_timeout", o.response_timeout},
        {"timeout", o.ack_timeout}, {"hold_timeout", o.hold_timeout}}) {
    if (!PositiveFinite(value)) {
      throw ConfigError(fmt::format("{}: {} = {} s: expected a positive time", who, name, value));
    }
  }
  const double metres = units.metres_per_length_unit;
  const std::string& unit = units.length_name;
  if (!o.position_tolerance) o.position_tolerance = 1e-3 / metres;                      // 1 mm
  if (!o.force_plausible) o.force_plausible = 1e6 / units.newtons_per_force_unit;  // 1 MN
  if (!o.settle_tolerance) o.settle_tolerance = InBenchUnit(kDefaultSettleTolerance, metres);
  if (!PositiveFinite(*o.settle_tolerance)) {
    throw ConfigError(fmt::format("{}: settle_tolerance = {} {}: expected a positive distance in "
                                  "the bench length unit (the controller's in-position window)",
                                  who, *o.settle_tolerance, unit));
  }
  if (!o.following_error) {
    o.following_error = DefaultFollowingError(*o.settle_tolerance,
                                              InBenchUnit(SafetyLimits{}.max_increment, metres));
  }
  if (!(o.poll_interval >= 0.0) || !std::isfinite(o.poll_interval) ||
      !PositiveFinite(*o.position_tolerance) || !PositiveFinite(*o.force_plausible)) {
    throw ConfigError(fmt::format(
        "{}: poll_interval = {} s, position_tolerance = {}, force_plausible = {}: expected a "
        "non-negative interval and positive plausibility bounds", who, o.poll_interval,
        *o.position_tolerance, *o.force_plausible));
  }
  if (!o.following_errors.empty() && o.following_errors.size() != actuators) {
    throw ConfigError(fmt::format("{}: {} following errors for {} actuators: give one per "
                                  "actuator", who, o.following_errors.size(), actuators));
  }
  std::vector<SettledReadingCheck::Limits> settled;
  for (std::size_t k = 0; k < actuators; ++k) {
    const double limit = o.following_errors.empty() ? *o.following_error : o.following_errors[k];
    if (!PositiveFinite(limit)) {
      throw ConfigError(fmt::format("{}: following_error {} {}: expected a positive distance in "
                                    "the bench length unit", who, limit, unit));
    }
    settled.push_back({limit, *o.settle_tolerance});
  }
  return settled;
}

}  // namespace hybridtest::transfer
