// See client_config.h.
#include "hybridtest/transfer/openfresco/client_config.h"

#include <fmt/core.h>

#include <filesystem>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/auth.h"
#include "hybridtest/transfer/bench_config.h"
#include "hybridtest/transfer/openfresco/client.h"
#include "hybridtest/transfer/socket.h"

namespace hybridtest::transfer::openfresco {

ClientOptions ParseClientOptions(const YamlInput& in, const YAML::Node& node,
                                 const std::string& kp,
                                 const std::optional<std::string>& bench_address,
                                 double reply_timeout) {
  in.CheckKeys(node, kp, {"type", "host", "port", "units", "timeout", "token", "token_file"});
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
  // The token is a secret: never in the run config, whose text is copied into the results
  // (the sidecar, report.html, the HDF5 export).
  if (node["token"]) {
    throw ConfigError(fmt::format(
        "{}: a token written in the run config would be copied into the results (.meta.json, "
        "report.html, HDF5 export); remove `token:`, put the token in a file and give "
        "`token_file: PATH` (relative to the run config), or set {}",
        in.Where(node["token"], kp + ".token"), kTokenEnvironmentVariable));
  }
  if (node["token_file"]) {
    std::filesystem::path file =
        in.String(node["token_file"], kp + ".token_file", "the path of a file with the token");
    if (file.is_relative()) file = std::filesystem::path(in.path()).parent_path() / file;
    client.token = ReadTokenFile(file.string(), in.Where(node["token_file"], kp + ".token_file"));
  } else {
    client.token = TokenFromEnvironment();
  }
  client.reply_timeout = node["timeout"]
                             ? in.PositiveNumber(node["timeout"], kp + ".timeout", "seconds")
                             : reply_timeout;
  return client;
}

std::unique_ptr<TransferSystem> MakeClientTransfer(const YamlInput& in, const YAML::Node& node,
                                                   const std::string& kp,
                                                   const std::optional<std::string>& bench_address,
                                                   double reply_timeout) {
  return std::make_unique<Client>(ParseClientOptions(in, node, kp, bench_address, reply_timeout));
}

}  // namespace hybridtest::transfer::openfresco
