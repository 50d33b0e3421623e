// See modbus_config.h.
#include "hybridtest/transfer/modbus/modbus_config.h"

#include <fmt/core.h>

#include <algorithm>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/socket.h"

namespace hybridtest::transfer::modbus {

ModbusOptions ParseModbusOptions(const YamlInput& in, const YAML::Node& node,
                                 const std::string& kp,
                                 const std::optional<std::string>& bench_address,
                                 double default_timeout, const SafetyLimits* limits) {
  in.CheckKeys(node, kp, {"type", "host", "port", "unit_id", "timeout", "response_timeout",
                          "connect_timeout", "hold_timeout", "poll_interval", "plausibility",
                          "settle_tolerance", "following_error", "map"});
  ModbusOptions o;
  if (bench_address && !bench_address->empty()) {
    const HostPort hp = ParseHostPort(*bench_address, "--bench");
    o.host = hp.host;
    o.port = hp.port;
  } else {
    if (!node["host"]) {
      throw ConfigError(fmt::format("{}: a modbus transfer needs the controller's address: give "
                                    "`host:` (and `port:`, default 502) or --bench HOST:PORT",
                                    in.Where(node, kp)));
    }
    o.host = in.String(node["host"], kp + ".host", "the controller's host name or IP address");
    if (node["port"]) {
      const int port = in.Integer(node["port"], kp + ".port", "a TCP port 1..65535 (Modbus: 502)");
      if (port < 1 || port > 65535) {
        in.ThrowValue(node["port"], kp + ".port", "a TCP port 1..65535 (Modbus: 502)");
      }
      o.port = static_cast<std::uint16_t>(port);
    }
  }
  if (node["unit_id"]) {
    o.unit_id = in.Integer(node["unit_id"], kp + ".unit_id", "a Modbus unit id 0..255");
    if (o.unit_id < 0 || o.unit_id > 255) {
      in.ThrowValue(node["unit_id"], kp + ".unit_id", "a Modbus unit id 0..255 (usually 1)");
    }
  }
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
  if (const YAML::Node p = in.Mapping(node, "plausibility", kp + ".plausibility", false);
      p.IsDefined()) {
    const std::string pkp = kp + ".plausibility";
    in.CheckKeys(p, pkp, {"position_tolerance", "force"});
    if (p["position_tolerance"]) {
      o.position_tolerance = in.PositiveNumber(
          p["position_tolerance"], pkp + ".position_tolerance",
          "the largest |position − command| of the first exchange, in bench length units");
    }
    if (p["force"]) {
      o.force_plausible = in.PositiveNumber(
          p["force"], pkp + ".force", "the largest |force| of the first exchange, in bench force units");
    }
  }
  o.maps = ParseRegisterMaps(in, node["map"], kp + ".map");
  // The controller's settling window and the following error, in the map's length unit; the
  // following error by default four settling windows, at most the slot's max_increment.
  const SafetyLimits l = limits != nullptr ? *limits : SafetyLimits{};
  const double metres = o.maps[0].units.metres_per_length_unit;
  o.settle_tolerance = InBenchUnit(kDefaultSettleTolerance, metres);
  if (const YAML::Node t = node["settle_tolerance"]; t.IsDefined()) {
    const std::string tkp = kp + ".settle_tolerance";
    o.settle_tolerance = in.PositiveNumber(
        t, tkp, fmt::format("the controller's settling (in-position) window, in the map's "
                            "length unit ({})", o.maps[0].units.length_name));
    if (*o.settle_tolerance * metres > l.max_increment) {
      throw ConfigError(fmt::format(
          "{}: {} {} is wider than the slot's safety.max_increment ({} {}): a controller that "
          "calls a move settled that far from its target has not settled; give the window in {} "
          "(the map's length unit), typically 0.01 to 0.1 mm", in.Where(t, tkp),
          *o.settle_tolerance, o.maps[0].units.length_name, l.max_increment / metres,
          o.maps[0].units.length_name, o.maps[0].units.length_name));
    }
  }
  if (const YAML::Node f = node["following_error"]; f.IsDefined()) {
    const std::string fkp = kp + ".following_error";
    const std::string what = fmt::format(
        "the largest |command − measured position| after a move, in the map's length unit ({})",
        o.maps[0].units.length_name);
    // A list: one limit per actuator of the map.
    const std::size_t n = o.maps.size();
    std::vector<double> errors;  // [map length unit]
    if (f.IsSequence()) {
      if (f.size() != n) {
        throw ConfigError(fmt::format("{}: {} values for the map's {} actuator{}: give one "
                                      "limit per actuator, or one for all",
                                      in.Where(f, fkp), f.size(), n, n == 1 ? "" : "s"));
      }
      for (std::size_t k = 0; k < n; ++k) {
        errors.push_back(in.PositiveNumber(f[k], fmt::format("{}[{}]", fkp, k), what));
      }
    } else {
      errors.push_back(in.PositiveNumber(f, fkp, what));
    }
    for (double limit : errors) {
      if (limit * metres > l.stroke_max - l.stroke_min) {
        throw ConfigError(fmt::format(
            "{}: {} {} is longer than the whole stroke ({} m to {} m), so it "
            "could never stop anything: give it in {} (the map's length unit), e.g. the slot's "
            "max_increment {} {}", in.Where(f, fkp), limit, o.maps[0].units.length_name,
            l.stroke_min, l.stroke_max, o.maps[0].units.length_name, l.max_increment / metres,
            o.maps[0].units.length_name));
      }
    }
    o.following_error = errors[0];
    if (f.IsSequence() && n > 1) o.following_errors = errors;
  } else {
    o.following_error =
        DefaultFollowingError(*o.settle_tolerance, InBenchUnit(l.max_increment, metres));
  }
  return o;
}

}  // namespace hybridtest::transfer::modbus
