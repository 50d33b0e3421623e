// See modbus_config.h.
#include "hybridtest/transfer/modbus/modbus_config.h"

#include <fmt/core.h>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/controller_options.h"
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
  o.maps = ParseRegisterMaps(in, node["map"], kp + ".map");
  // The timeouts, the first exchange's plausibility, the settling window and the following
  // errors, in the map's units.
  ReadControllerOptions(in, node, kp, default_timeout, limits, o.maps[0].units, o.maps.size(), o);
  return o;
}

}  // namespace hybridtest::transfer::modbus
