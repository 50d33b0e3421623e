// See ads_config.h.
#include "hybridtest/transfer/ads/ads_config.h"

#include <fmt/core.h>

#include <algorithm>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/bench_config.h"
#include "hybridtest/transfer/socket.h"

namespace hybridtest::transfer::ads {
namespace {

AmsNetId ReadNetId(const YamlInput& in, const YAML::Node& node, const std::string& key) {
  const std::string text = in.String(node, key, "an AmsNetId (six numbers 0..255: 5.80.201.232.1.1)");
  const std::optional<AmsNetId> id = ParseAmsNetId(text);
  if (!id) in.ThrowValue(node, key, "an AmsNetId: six numbers 0..255 joined by dots, e.g. 5.80.201.232.1.1");
  return *id;
}

std::uint16_t ReadPort(const YamlInput& in, const YAML::Node& node, const std::string& key,
                       const char* expected) {
  const int port = in.Integer(node, key, expected);
  if (port < 1 || port > 65535) in.ThrowValue(node, key, expected);
  return static_cast<std::uint16_t>(port);
}

// The per-actuator following errors (one value, or one per actuator) [bench length unit].
std::vector<double> ReadFollowingErrors(const YamlInput& in, const YAML::Node& f,
                                        const std::string& fkp, int n, const std::string& unit) {
  const std::string what = fmt::format(
      "the largest |command − measured position| after a move, in the length unit ({})", unit);
  if (!f.IsSequence()) return {in.PositiveNumber(f, fkp, what)};
  if (f.size() != static_cast<std::size_t>(n)) {
    throw ConfigError(fmt::format("{}: {} values for {} actuator{}: give one limit per actuator, "
                                  "or one for all", in.Where(f, fkp), f.size(), n,
                                  n == 1 ? "" : "s"));
  }
  std::vector<double> out;
  for (std::size_t k = 0; k < f.size(); ++k) {
    out.push_back(in.PositiveNumber(f[k], fmt::format("{}[{}]", fkp, k), what));
  }
  return out;
}

}  // namespace

AdsOptions ParseAdsOptions(const YamlInput& in, const YAML::Node& node, const std::string& kp,
                           const std::optional<std::string>& bench_address,
                           double default_timeout, const SafetyLimits* limits) {
  in.CheckKeys(node, kp, {"type", "host", "port", "ams_net_id", "ams_port", "local_ams_net_id",
                          "local_ams_port", "actuators", "units", "symbols", "timeout",
                          "response_timeout", "connect_timeout", "hold_timeout", "poll_interval",
                          "plausibility", "settle_tolerance", "following_error"});
  AdsOptions o;
  AdsEndpoint& e = o.endpoint;
  if (bench_address && !bench_address->empty()) {
    const HostPort hp = ParseHostPort(*bench_address, "--bench");
    e.host = hp.host;
    e.tcp_port = hp.port;
  } else {
    if (!node["host"]) {
      throw ConfigError(fmt::format("{}: an ads transfer needs the PLC's address: give `host:` "
                                    "(and `port:`, default 48898) or --bench HOST:PORT",
                                    in.Where(node, kp)));
    }
    e.host = in.String(node["host"], kp + ".host", "the PLC's host name or IP address");
    if (node["port"]) {
      e.tcp_port = ReadPort(in, node["port"], kp + ".port", "a TCP port 1..65535 (ADS: 48898)");
    }
  }
  if (node["ams_net_id"]) {
    e.target.net_id = ReadNetId(in, node["ams_net_id"], kp + ".ams_net_id");
  } else if (auto id = ParseAmsNetId(e.host + ".1.1")) {
    e.target.net_id = *id;  // TwinCAT's usual AmsNetId: the IPv4 address and .1.1
  } else {
    throw ConfigError(fmt::format("{}: host '{}' is not an IPv4 address, so the PLC's AmsNetId "
                                  "cannot be guessed from it: give `ams_net_id:` (TwinCAT: "
                                  "System > Routes > NetId Management)", in.Where(node, kp),
                                  e.host));
  }
  if (node["ams_port"]) {
    e.target.port = ReadPort(in, node["ams_port"], kp + ".ams_port",
                             "an AMS port (851: TwinCAT 3 PLC runtime 1; 801: TwinCAT 2)");
  }
  if (node["local_ams_net_id"]) {
    e.local_net_id = ReadNetId(in, node["local_ams_net_id"], kp + ".local_ams_net_id");
  }
  if (node["local_ams_port"]) {
    e.local_port = ReadPort(in, node["local_ams_port"], kp + ".local_ams_port", "an AMS port 1..65535");
  }
  int n = 1;
  if (node["actuators"]) {
    n = static_cast<int>(in.Count(node["actuators"], kp + ".actuators",
                                  "the number of actuators (the arrays' length)", 1, 64));
  }
  o.profile = DefaultProfile(n);
  if (node["units"]) o.profile.units = ParseBenchUnits(node["units"], in.Where(node["units"], kp + ".units"));
  if (const YAML::Node s = in.Mapping(node, "symbols", kp + ".symbols", false); s.IsDefined()) {
    for (const auto& entry : s) {
      const std::string key = entry.first.as<std::string>();
      std::size_t r = 0;
      while (r < kNumRoles && key != RoleKey(static_cast<Role>(r))) ++r;
      if (r == kNumRoles) {
        std::string keys;
        for (std::size_t i = 0; i < kNumRoles; ++i) keys += (i ? ", " : "") + std::string(RoleKey(static_cast<Role>(i)));
        throw ConfigError(fmt::format("{}: unknown symbol role '{}': expected one of {}",
                                      in.Where(entry.first, kp + ".symbols"), key, keys));
      }
      o.profile.symbols[r] = in.String(entry.second, kp + ".symbols." + key,
                                       "a PLC variable's name, e.g. " + DefaultSymbol(static_cast<Role>(r)));
    }
  }
  const auto seconds = [&](const char* key, double fallback) {
    return node[key] ? in.PositiveNumber(node[key], kp + "." + key, "a time in seconds") : fallback;
  };
  o.ack_timeout = seconds("timeout", default_timeout);
  o.response_timeout = seconds("response_timeout", std::min(o.response_timeout, o.ack_timeout));
  o.connect_timeout = seconds("connect_timeout", o.connect_timeout);
  o.hold_timeout = seconds("hold_timeout", o.hold_timeout);
  o.poll_interval = in.ReadNumber(node, kp, "poll_interval", "a pause in seconds (0: back to back)",
                                  o.poll_interval);
  if (o.poll_interval < 0.0) {
    in.ThrowValue(node["poll_interval"], kp + ".poll_interval", "a non-negative time in seconds");
  }
  if (const YAML::Node p = in.Mapping(node, "plausibility", kp + ".plausibility", false); p.IsDefined()) {
    in.CheckKeys(p, kp + ".plausibility", {"position_tolerance", "force"});
    if (p["position_tolerance"]) {
      o.position_tolerance = in.PositiveNumber(p["position_tolerance"], kp + ".plausibility.position_tolerance",
                                               "a length in the bench length unit");
    }
    if (p["force"]) {
      o.force_plausible = in.PositiveNumber(p["force"], kp + ".plausibility.force",
                                            "a force in the bench force unit");
    }
  }
  // The in-position window and the following error (the Modbus transfer's rules).
  const SafetyLimits l = limits != nullptr ? *limits : SafetyLimits{};
  const double metres = o.profile.units.metres_per_length_unit;
  const std::string& unit = o.profile.units.length_name;
  o.settle_tolerance = InBenchUnit(kDefaultSettleTolerance, metres);
  if (node["settle_tolerance"]) {
    o.settle_tolerance = in.PositiveNumber(node["settle_tolerance"], kp + ".settle_tolerance",
                                           "the PLC's in-position window, in " + unit);
    if (*o.settle_tolerance * metres > l.max_increment) {
      in.ThrowValue(node["settle_tolerance"], kp + ".settle_tolerance",
                    fmt::format("a window narrower than the slot's max_increment ({} {})",
                                l.max_increment / metres, unit));
    }
  }
  if (node["following_error"]) {
    o.following_errors = ReadFollowingErrors(in, node["following_error"],
                                             kp + ".following_error", n, unit);
    for (double limit : o.following_errors) {
      if (limit * metres > l.stroke_max - l.stroke_min) {
        in.ThrowValue(node["following_error"], kp + ".following_error",
                      fmt::format("a limit shorter than the stroke, in {} (e.g. the slot's "
                                  "max_increment, {} {})", unit, l.max_increment / metres, unit));
      }
    }
    o.following_error = o.following_errors[0];
    if (o.following_errors.size() == 1) o.following_errors.clear();
  } else {
    o.following_error = DefaultFollowingError(*o.settle_tolerance, InBenchUnit(l.max_increment, metres));
  }
  return o;
}

}  // namespace hybridtest::transfer::ads
