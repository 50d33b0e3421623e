// See transfer_readers.h.
#include "hybridtest/io/transfer_readers.h"

#include <fmt/core.h>

#include <algorithm>
#include <filesystem>
#include <map>

#include "hybridtest/common/error.h"
#include "hybridtest/constitutive/parse_law.h"
#include "hybridtest/fmi/fmu_plant.h"
#include "hybridtest/io/rt_plant_reader.h"
#include "hybridtest/transfer/ads/ads_config.h"
#include "hybridtest/transfer/auth.h"
#include "hybridtest/transfer/bench_client.h"
#include "hybridtest/transfer/emulated_bench.h"
#include "hybridtest/transfer/modbus/modbus_config.h"
#include "hybridtest/transfer/modbus/modbus_transfer.h"
#include "hybridtest/transfer/numerical_loopback.h"
#include "hybridtest/transfer/openfresco/client.h"
#include "hybridtest/transfer/openfresco/client_config.h"
#include "hybridtest/transfer/site/site_client.h"
#include "hybridtest/transfer/socket.h"

namespace hybridtest::io {
namespace {

using substructures::TransferSpec;

// A path in the config, relative to the config's folder.
std::string ConfigRelative(const TransferReadContext& c, const YAML::Node& node,
                           const std::string& key, const char* expected) {
  std::filesystem::path file = c.in.String(node, c.kp + "." + key, expected);
  if (file.is_relative()) file = std::filesystem::path(c.in.path()).parent_path() / file;
  return file.string();
}

// The emulated bench of a spec read once, of one actuator or of `actuators: n`.
TransferSpec Emulated(transfer::EmulatedBenchSpec bench) {
  return {"emulated", [bench = std::move(bench)]() -> std::unique_ptr<transfer::TransferSystem> {
            return transfer::MakeEmulatedBench(bench);
          }};
}

TransferSpec ReadEmulated(const TransferReadContext& c) {
  c.in.CheckKeys(c.node, c.kp, {"type", "config", "bench"});
  // One bench file or mapping, read once, of one actuator or of `actuators: n`.
  if (c.node["config"]) {
    const std::string path = ConfigRelative(c, c.node["config"], "config", "a bench file");
    TransferSpec spec = EmulatedTransfer(path);
    c.NoteRead("bench", path);
    return spec;
  }
  if (c.node["bench"]) {
    return Emulated(transfer::ParseEmulatedBenchSpec(
        c.node["bench"], c.in.Where(c.node["bench"], c.kp + ".bench")));
  }
  throw ConfigError(fmt::format("{}: an emulated transfer needs `config: FILE` (a bench file) "
                                "or an inline `bench:` mapping", c.in.Where(c.node, c.kp)));
}

// One law (a mapping) and one p0 per actuator: `law: {...}` and `p0: x` for one actuator, or
// `law: [{...}, {...}]` and `p0: [x1, x2]` for n (a number p0: every actuator).
TransferSpec ReadLoopback(const TransferReadContext& c) {
  c.in.CheckKeys(c.node, c.kp, {"type", "law", "p0"});
  const YAML::Node node = c.node["law"];
  if (!node) {
    throw ConfigError(fmt::format("{}: a loopback transfer needs `law:` (e.g. {{type: linear, "
                                  "stiffness: 7200}}, or a list of one law per actuator)",
                                  c.in.Where(c.node, c.kp)));
  }
  const std::string lkp = c.kp + ".law";
  std::vector<std::shared_ptr<const constitutive::RestoringForceLaw>> laws;
  if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i) {
      const std::string ikp = fmt::format("{}[{}]", lkp, i);
      laws.push_back(constitutive::ParseRestoringForceLaw(node[i], c.in.Where(node[i], ikp)));
    }
    if (laws.empty()) c.in.ThrowValue(node, lkp, "a law, or a list of one law per actuator");
  } else {
    laws.push_back(constitutive::ParseRestoringForceLaw(node, c.in.Where(node, lkp)));
  }
  std::vector<double> p0(laws.size(), 0.0);
  if (const YAML::Node p = c.node["p0"]) {
    if (p.IsSequence()) {
      p0 = c.in.Numbers(p, c.kp + ".p0", "positions in m");
      if (p0.size() != laws.size()) {
        c.in.ThrowValue(p, c.kp + ".p0",
                        fmt::format("{} positions in m, one per law (actuator)", laws.size()));
      }
    } else {
      p0.assign(laws.size(), c.in.Number(p, c.kp + ".p0", "a position in m"));
    }
  }
  return {"loopback", [laws, p0] {
            std::vector<std::unique_ptr<constitutive::RestoringForceLaw>> own;
            for (const auto& law : laws) own.push_back(law->Clone());
            return std::make_unique<transfer::NumericalLoopback>(std::move(own), p0);
          }};
}

TransferSpec ReadRemote(const TransferReadContext& c) {
  const YamlInput& in = c.in;
  const YAML::Node& node = c.node;
  const std::string& kp = c.kp;
  in.CheckKeys(node, kp, {"type", "address", "token", "token_file", "timeout"});
  transfer::BenchClientOptions client;
  std::string address = c.bench_address.value_or("");
  if (address.empty() && node["address"]) {
    address = in.String(node["address"], kp + ".address", "HOST:PORT");
  }
  if (address.empty()) {
    throw ConfigError(fmt::format("{}: a remote transfer needs the bench server's address: give "
                                  "--bench HOST:PORT or `address: HOST:PORT`", in.Where(node, kp)));
  }
  const transfer::HostPort hp = transfer::ParseHostPort(address, "--bench / " + kp + ".address");
  client.host = hp.host;
  client.port = hp.port;
  client.token = ReadTransferToken(c);
  if (c.limits != nullptr) {
    client.expected_limits = *c.limits;
    client.limits_where = kp.substr(0, kp.rfind('.')) + ".safety";
  }
  client.reply_timeout =
      node["timeout"] ? in.PositiveNumber(node["timeout"], kp + ".timeout", "seconds")
                      : c.reply_timeout;
  return {"remote", [client] { return std::make_unique<transfer::BenchClient>(client); }};
}

TransferSpec ReadModbus(const TransferReadContext& c) {
  auto modbus = transfer::modbus::ParseModbusOptions(c.in, c.node, c.kp, c.bench_address,
                                                     c.reply_timeout, c.limits);
  return {"modbus", [modbus] { return std::make_unique<transfer::modbus::ModbusTransfer>(modbus); }};
}

TransferSpec ReadAds(const TransferReadContext& c) {
  auto ads = transfer::ads::ParseAdsOptions(c.in, c.node, c.kp, c.bench_address, c.reply_timeout,
                                            c.limits);
  return {"ads", [ads] { return std::make_unique<transfer::ads::AdsTransfer>(ads); }};
}

TransferSpec ReadOpenFresco(const TransferReadContext& c) {
  auto client = transfer::openfresco::ParseClientOptions(c.in, c.node, c.kp, c.bench_address,
                                                         c.reply_timeout);
  if (!client.token_file.empty()) c.NoteRead("token", client.token_file);
  return {"openfresco",
          [client] { return std::make_unique<transfer::openfresco::Client>(client); }};
}

// An FMU as the plant of an emulated bench (fmi/fmu_plant.h); its file is a run input.
TransferSpec ReadFmuPlant(const TransferReadContext& c) {
  std::string file;
  TransferSpec spec = fmi::ParseFmuPlant(c.in, c.node, c.kp, &file);
  c.NoteRead("fmu", file);
  return spec;
}

TransferSpec ReadSite(const TransferReadContext& c) {
  c.in.CheckKeys(c.node, c.kp, {"type", "address", "token", "token_file", "actuators",
                                "connect_timeout", "propose_timeout", "execute_timeout",
                                "reconnect_wait", "run"});
  transfer::site::SiteClientOptions o;
  o.name = c.kp.substr(0, c.kp.rfind('.'));
  if (!c.node["address"]) {
    throw ConfigError(fmt::format("{}: a site transfer needs `address: HOST:PORT` (where "
                                  "`hybridtest site` listens)", c.in.Where(c.node, c.kp)));
  }
  const transfer::HostPort hp = transfer::ParseHostPort(
      c.in.String(c.node["address"], c.kp + ".address", "HOST:PORT"), c.kp + ".address");
  o.host = hp.host;
  o.port = hp.port;
  o.token = ReadTransferToken(c);
  if (const YAML::Node n = c.node["actuators"]) {
    o.actuators = c.in.Integer(n, c.kp + ".actuators", "the site's actuators, 1 to 1024");
    if (o.actuators < 1 || o.actuators > 1024) {
      c.in.ThrowValue(n, c.kp + ".actuators", "the site's actuators, 1 to 1024");
    }
  }
  const auto time = [&](const char* key, double& value) {
    if (const YAML::Node n = c.node[key]) {
      value = c.in.PositiveNumber(n, c.kp + "." + key, "a time in seconds");
    }
  };
  o.execute_timeout = std::max(o.execute_timeout, 2.0 * c.reply_timeout);
  time("connect_timeout", o.connect_timeout);
  time("propose_timeout", o.propose_timeout);
  time("execute_timeout", o.execute_timeout);
  time("reconnect_wait", o.reconnect_wait);
  if (const YAML::Node n = c.node["run"]) o.run = c.in.String(n, c.kp + ".run", "a run tag");
  return {"site", [o] { return std::make_unique<transfer::site::SiteClient>(o); }};
}

std::map<std::string, TransferReader>& Readers() {
  static std::map<std::string, TransferReader> readers{{"emulated", ReadEmulated},
                                                       {"loopback", ReadLoopback},
                                                       {"remote", ReadRemote},
                                                       {"site", ReadSite},
                                                       {"modbus", ReadModbus},
                                                       {"ads", ReadAds},
                                                       {"openfresco", ReadOpenFresco},
                                                       {"rt_plant", ReadRtPlant},
                                                       {"compensated", ReadCompensated},
                                                       {"fmu", ReadFmuPlant}};
  return readers;
}

std::string TypeList() {
  std::string list;
  for (const auto& type : TransferTypes()) list += (list.empty() ? "" : ", ") + type;
  return list;
}

}  // namespace

std::string ReadTransferToken(const TransferReadContext& c) {
  // The token is a secret: never in the config, whose text is copied into the results.
  if (c.node["token"]) {
    throw ConfigError(fmt::format(
        "{}: a token written in the run config would be copied into the results (.meta.json); "
        "put it in a file and give `token_file: PATH`, or set {}", c.in.Where(c.node["token"],
        c.kp + ".token"), transfer::kTokenEnvironmentVariable));
  }
  if (c.node["token_file"]) {
    const std::string path =
        ConfigRelative(c, c.node["token_file"], "token_file", "the path of a file with the token");
    c.NoteRead("token", path);
    return transfer::ReadTokenFile(path, c.in.Where(c.node["token_file"], c.kp + ".token_file"));
  }
  return transfer::TokenFromEnvironment();
}

void RegisterTransferReader(const std::string& type, TransferReader reader) {
  if (type.empty() || !reader) {
    throw ConfigError("RegisterTransferReader: give a type name and a reader");
  }
  Readers()[type] = std::move(reader);
}

std::vector<std::string> TransferTypes() {
  std::vector<std::string> types;
  for (const auto& [type, reader] : Readers()) types.push_back(type);
  return types;  // a std::map is sorted
}

substructures::TransferSpec EmulatedTransfer(const std::string& path) {
  return Emulated(transfer::LoadEmulatedBenchSpec(path));
}

substructures::TransferSpec ReadTransfer(const TransferReadContext& c) {
  const std::string type = c.in.String(c.node["type"], c.kp + ".type",
                                       ("a transfer type: " + TypeList()).c_str());
  const auto it = Readers().find(type);
  if (it == Readers().end()) {
    throw ConfigError(fmt::format("{} = '{}': expected one of {}",
                                  c.in.Where(c.node["type"], c.kp + ".type"), type, TypeList()));
  }
  return it->second(c);
}

}  // namespace hybridtest::io
