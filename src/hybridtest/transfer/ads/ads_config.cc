// See ads_config.h.
#include "hybridtest/transfer/ads/ads_config.h"

#include <fmt/core.h>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/bench_config.h"
#include "hybridtest/transfer/controller_options.h"
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
  // The timeouts, the first exchange's plausibility, the in-position window and the following
  // errors, in the profile's units.
  ReadControllerOptions(in, node, kp, default_timeout, limits, o.profile.units,
                        static_cast<std::size_t>(n), o);
  return o;
}

}  // namespace hybridtest::transfer::ads
