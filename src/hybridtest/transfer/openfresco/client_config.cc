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
namespace {

// The substructure whose `transfer:` is at `kp` ("substructures.NAME.transfer"), found from
// the document's root; an undefined node when kp does not lead to one.
YAML::Node SubstructureOf(const YamlInput& in, const std::string& kp) {
  const std::string suffix = ".transfer";
  if (kp.size() <= suffix.size() || kp.compare(kp.size() - suffix.size(), suffix.size(), suffix) != 0) {
    return YAML::Node(YAML::NodeType::Undefined);
  }
  const std::string path = kp.substr(0, kp.size() - suffix.size());
  YAML::Node node = in.root();
  std::size_t at = 0;
  while (at <= path.size()) {
    const std::size_t dot = std::min(path.find('.', at), path.size());
    const YAML::Node& here = node;
    const YAML::Node child = here.IsMap() ? here[path.substr(at, dot - at)] : YAML::Node();
    if (!child.IsDefined() || child.IsNull()) return YAML::Node(YAML::NodeType::Undefined);
    node.reset(child);  // rebinds the handle; never writes into the document
    at = dot + 1;
  }
  return node.IsMap() ? node : YAML::Node(YAML::NodeType::Undefined);
}

// The element's n must be the number of actuators the substructure drives: the rows of its
// `setup.transform` (several slots), else 1. Throws ConfigError naming `dofs` and the fix.
void CheckDofsAgainstSubstructure(const YamlInput& in, const YAML::Node& node,
                                  const std::string& kp, int dofs) {
  const YAML::Node sub = SubstructureOf(in, kp);
  if (!sub.IsDefined()) return;  // not a run config's substructure: nothing to compare with
  const auto defined = [](const YAML::Node& n) { return n.IsDefined() && !n.IsNull(); };
  const YAML::Node setup = sub["setup"];
  const YAML::Node transform =
      defined(setup) && setup.IsMap() ? setup["transform"] : YAML::Node();
  int channels = 1;
  std::string what = "serves one slot";
  if (defined(transform) && transform.IsSequence()) {
    channels = static_cast<int>(transform.size());
    what = fmt::format("drives {} actuator{} (the rows of its setup.transform)", channels,
                       channels == 1 ? "" : "s");
  } else if (defined(sub["slots"]) && sub["slots"].IsSequence()) {
    channels = static_cast<int>(sub["slots"].size());
    what = fmt::format("serves {} slots", channels);
  }
  if (channels == dofs) return;
  const std::string name = kp.substr(0, kp.size() - std::string(".transfer").size());
  std::string identity, zeros;
  for (int i = 0; i < dofs; ++i) {
    zeros += i == 0 ? "0" : ", 0";
    identity += i == 0 ? "[" : ", [";
    for (int j = 0; j < dofs; ++j) identity += fmt::format("{}{}", j == 0 ? "" : ", ", i == j ? 1 : 0);
    identity += "]";
  }
  const std::string fix =
      dofs == 1 ? fmt::format("give `dofs: {}` (one degree of freedom per actuator)", channels)
                : fmt::format("give `dofs: {}`, or serve {} slots with `slots: [..]` and `setup: "
                              "{{p0: [{}], transform: [{}]}}` (the site applies its own setup)",
                              channels, dofs, zeros, identity);
  throw ConfigError(fmt::format(
      "{}: the OpenFresco element has dofs = {}{} but substructure {} {}: one degree of freedom "
      "of the element per actuator; {}",
      node["dofs"] ? in.Where(node["dofs"], kp + ".dofs") : in.Where(node, kp), dofs,
      node["dofs"] ? "" : " (the default: no `dofs:`)", name, what, fix));
}

}  // namespace

ClientOptions ParseClientOptions(const YamlInput& in, const YAML::Node& node,
                                 const std::string& kp,
                                 const std::optional<std::string>& bench_address,
                                 double reply_timeout) {
  in.CheckKeys(node, kp, {"type", "host", "port", "units", "timeout", "token", "token_file",
                             "dofs"});
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
    client.token_file = file.string();
  } else {
    client.token = TokenFromEnvironment();
  }
  if (node["dofs"]) {
    client.dofs = in.Integer(node["dofs"], kp + ".dofs", "the element's degrees of freedom");
    if (client.dofs < 1 || client.dofs > kMaxDofs) {
      in.ThrowValue(node["dofs"], kp + ".dofs",
                    fmt::format("the element's degrees of freedom, 1 to {}", kMaxDofs));
    }
  }
  CheckDofsAgainstSubstructure(in, node, kp, client.dofs);
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
