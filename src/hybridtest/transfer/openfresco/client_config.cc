// See client_config.h.
#include "hybridtest/transfer/openfresco/client_config.h"

#include <fmt/core.h>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/bench_config.h"
#include "hybridtest/transfer/openfresco/client.h"
#include "hybridtest/transfer/socket.h"

namespace hybridtest::transfer::openfresco {

std::unique_ptr<TransferSystem> MakeClientTransfer(const YamlInput& in, const YAML::Node& node,
                                                   const std::string& kp,
                                                   const std::optional<std::string>& bench_address,
                                                   double reply_timeout) {
  in.CheckKeys(node, kp, {"type", "host", "port", "units", "timeout", "token"});
  ClientOptions client;
  if (bench_address && !bench_address->empty()) {
    const HostPort hp = ParseHostPort(*bench_address, "--bench");
    client.host = hp.host;
    client.port = hp.port;
  } else {
    if (!node["host"] || !node["port"]) {
      throw ConfigError(fmt::format("{}: an openfresco transfer needs the site server's "
                                    "address: give `host:` and `port:` or --bench HOST:PORT",
                                    in.Where(node, kp)));
    }
    client.host = in.String(node["host"], kp + ".host", "a host name or IP address");
    const int port = in.Integer(node["port"], kp + ".port", "a TCP port (1 to 65535)");
    if (port < 1 || port > 65535) {
      in.ThrowValue(node["port"], kp + ".port", "a TCP port (1 to 65535)");
    }
    client.port = static_cast<std::uint16_t>(port);
  }
  if (node["units"]) {
    client.units = ParseBenchUnits(node["units"], in.Where(node["units"], kp + ".units"));
  }
  if (node["token"]) {
    client.token = in.String(node["token"], kp + ".token", "the bench's shared token");
  }
  client.reply_timeout = node["timeout"]
                             ? in.PositiveNumber(node["timeout"], kp + ".timeout", "seconds")
                             : reply_timeout;
  return std::make_unique<Client>(client);
}

}  // namespace hybridtest::transfer::openfresco
