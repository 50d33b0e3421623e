// `hybridtest bench`: serves the emulated test bench over TCP (bench protocol v1,
// docs/protocol.md) until SIGINT or SIGTERM.
//
//   hybridtest bench [--config FILE] [--listen HOST:PORT] [--token-file FILE]
//                    [--heartbeat-timeout S] [--inject KIND@N]...
//                    [--protocol hybridtest|openfresco|ads]
//   hybridtest bench --protocol ads [--config FILE] [--listen HOST:PORT] [--route NETID[@ADDR]]...
//                    [--ams-net-id NETID] [--plc-state run|stop] [--inject KIND@N]...
//                    [--plc-program instant|p_hybrid] [--watchdog S]
//   hybridtest bench --real-time CONFIG [--tick S] [--listen HOST:PORT] ...
//
// --real-time serves the emulated real-time plant (rt_plant) of the run config's first
// physical slot — the plant under a compensator; the compensator stays with the client — on
// the server's own monotonic clock: between two commands the plant runs on, holding the last
// command, and each command is answered with the measurement of that moment
// (docs/real-time.md, "Over TCP"). The safety limits and p0 are the slot's.
//
// --protocol openfresco serves OpenFresco's generic TCP protocol instead (OpenSees's
// `expElement genericClient`; docs/openfresco.md), with the config's `openfresco:` setup (one
// row of its transform per actuator for a bench file with `actuators:`).
//
// --protocol ads serves the bench as a TwinCAT PLC emulator over ADS (docs/ads.md): the
// profile's GVL_Hybrid variables by symbol name on AMS/TCP (default 127.0.0.1:48898), AMS
// port 851, only for the AmsNetIds given with --route, each from its address (any on
// loopback without one);
// --plc-state stop rehearses a PLC that is not running; --inject takes the ADS emulator's
// test faults (fault, silence, close, ads_error, holding; transfer/ads/ads_server.h);
// --plc-program p_hybrid runs docs/ads.md's Structured Text P_Hybrid cyclically, its heartbeat
// watchdog (--watchdog S, tWatchdog's PT) included.
//
// The token comes from --token-file or the environment (HYBRIDTEST_BENCH_TOKEN), never from
// the command line, which every user of the machine can read in /proc/PID/cmdline.
//
// Prints one line "hybridtest bench: listening on HOST:PORT (...)" to stdout once it accepts
// connections (port 0 picks a free port; the line shows the one chosen), then logs events to
// stderr.
#include <fmt/core.h>

#include <csignal>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli_values.h"
#include "command.h"
#include "serve_until_signal.h"
#include "server_token.h"
#include "hybridtest/common/clock.h"
#include "hybridtest/common/error.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/transfer/ads/ads_server.h"
#include "hybridtest/transfer/delay_compensator.h"
#include "hybridtest/transfer/rt_plant.h"
#include "hybridtest/transfer/auth.h"
#include "hybridtest/transfer/bench_config.h"
#include "hybridtest/transfer/bench_server.h"
#include "hybridtest/transfer/emulated_bench.h"
#include "hybridtest/transfer/bench_spec.h"
#include "hybridtest/transfer/openfresco/server.h"
#include "hybridtest/transfer/openfresco/setup_config.h"

namespace hybridtest::app {
namespace {

struct BenchArgs {
  std::string config;
  std::string listen = "127.0.0.1:7471";
  ServerTokenOptions token;
  double heartbeat_timeout = 10.0;
  std::vector<std::string> inject;
  std::string protocol = "hybridtest";
  std::string real_time;  // a run config whose first physical slot's rt_plant is served
  double tick = 0.001;    // [s] the client's tick (the plant's hold between commands)
  bool listen_given = false;       // --listen was given (ads: default port 48898)
  std::vector<std::string> routes;  // ads: AmsNetIds served
  std::string ams_net_id = "127.0.0.1.1.1";  // ads: the emulated PLC's AmsNetId
  std::string plc_state = "run";             // ads: what ReadState shows
  std::string plc_program = "instant";       // ads: instant or p_hybrid (docs/ads.md)
  double watchdog = 2.0;                     // ads, p_hybrid: tWatchdog's PT [s]
};

// --protocol openfresco: the same bench and options, served by the OpenFresco server with the
// config's `openfresco:` setup (T of one row per actuator). In the `actuators:` form the
// coupled prediction uses the section's `initial_stiffness` matrix, else the specimen's.
void ServeOpenFresco(const BenchArgs& args, const transfer::EmulatedBenchSpec& spec,
                     transfer::TransferSystem& bench, transfer::BenchServerOptions options) {
  if (args.config.empty()) {
    throw ConfigError("--protocol openfresco needs --config FILE with an `openfresco:` section "
                      "(see examples/rotor/bench-openfresco.yaml)");
  }
  transfer::openfresco::ExpSetup setup = transfer::openfresco::LoadSetup(args.config, spec);
  options.actuator_stiffness.reset();  // the server takes the setup's K_a
  transfer::openfresco::Server server(bench, std::move(setup), options);
  if (server.setup().actuators == 1) {
    std::printf("hybridtest bench: listening on %s (OpenFresco protocol, n = %d; %s; token %s)\n",
                server.address().c_str(), server.setup().dofs(), bench.Describe().c_str(),
                options.token.empty() ? "none" : "required");
  } else {
    std::printf("hybridtest bench: listening on %s (OpenFresco protocol, n = %d, %d actuators; "
                "%s; token %s)\n", server.address().c_str(), server.setup().dofs(),
                server.setup().actuators, bench.Describe().c_str(),
                options.token.empty() ? "none" : "required");
  }
  std::fflush(stdout);
  ServeUntilSignal(server);
}

// --protocol ads: the bench as a TwinCAT PLC emulator (transfer/ads/ads_server.h).
void ServeAds(const BenchArgs& args, const transfer::EmulatedBenchSpec& spec) {
  using namespace transfer;
  const HostPort listen =
      ParseHostPort(args.listen_given ? args.listen : "127.0.0.1:48898", "--listen");
  ads::AdsServerOptions o;
  o.host = listen.host;
  o.port = listen.port;
  const auto net_id = [](const std::string& text, const char* where) {
    const auto id = ads::ParseAmsNetId(text);
    if (!id) {
      throw ConfigError(fmt::format("{} {}: expected an AmsNetId, six numbers 0..255 joined by "
                                    "dots (e.g. 192.168.0.5.1.1)", where, text));
    }
    return *id;
  };
  o.address.net_id = net_id(args.ams_net_id, "--ams-net-id");
  for (const std::string& r : args.routes) o.routes.push_back(ads::ParseAdsRoute(r, "--route"));
  o.ads_state = args.plc_state == "run" ? ads::kStateRun : ads::kStateStop;
  for (const std::string& f : args.inject) o.faults.push_back(ads::ParseAdsFault(f, "--inject"));
  if (args.plc_program == "p_hybrid") o.program = ads::PlcProgram::kPHybrid;
  o.watchdog = args.watchdog;
  ads::UseBenchSafety(o, spec);
  o.log = [](const std::string& line) { std::fprintf(stderr, "hybridtest bench: %s\n", line.c_str()); };
  std::unique_ptr<TransferSystem> bench = MakeEmulatedBench(spec);
  ads::AdsServer server(*bench, o);
  const std::string program = o.program == ads::PlcProgram::kPHybrid
      ? fmt::format("P_Hybrid of docs/ads.md, watchdog {} s", o.watchdog) : "instant program";
  std::printf("hybridtest bench: listening on %s (ADS, TwinCAT PLC emulator: %s; PLC in %s, %s; %s%s)\n",
              server.address().c_str(), server.DescribeRoutes().c_str(),
              args.plc_state == "run" ? "RUN" : "STOP", program.c_str(), bench->Describe().c_str(),
              args.inject.empty() ? "" : "; TEST FAULTS INJECTED");
  std::fflush(stdout);
  ServeUntilSignal(server);
}

// --real-time CONFIG: the first physical slot's rt_plant, paced on this process's clock.
void ServeRealTime(const BenchArgs& args, transfer::BenchServerOptions options) {
  const io::RunSpec spec = io::LoadRunSpec(args.real_time);
  const substructures::SubstructureSpec* slot = nullptr;
  for (const auto& s : spec.substructures) {
    if (s.physical) {
      slot = &s;
      break;
    }
  }
  if (slot == nullptr) {
    throw ConfigError(fmt::format("--real-time {}: no physical slot to serve", args.real_time));
  }
  std::unique_ptr<transfer::TransferSystem> made = slot->physical->transfer.make();
  transfer::TransferSystem* plant = made->served_plant();
  if (plant == nullptr) {
    throw ConfigError(fmt::format("--real-time {}: slot {} is {}, not an emulated real-time "
                                  "plant (transfer type rt_plant)", args.real_time, slot->slot,
                                  made->Describe()));
  }
  options.limits = slot->physical->limits;
  options.start_position = slot->physical->setup.p0;
  if (slot->physical->initial_stiffness) {
    options.initial_stiffness = *slot->physical->initial_stiffness;
  }
  MonotonicClock clock;
  plant->StartPaced(args.tick, clock);
  transfer::BenchServer server(*plant, options);
  std::printf("hybridtest bench: listening on %s (real time on the server's clock, tick %g s: "
              "%s; token %s)\n", server.address().c_str(), args.tick, plant->Describe().c_str(),
              options.token.empty() ? "none" : "required");
  std::fflush(stdout);
  ServeUntilSignal(server);
}

void RunBench(const BenchArgs& args) {
  using namespace transfer;
  if (!args.real_time.empty() && (!args.config.empty() || args.protocol != "hybridtest" ||
                                  !args.inject.empty())) {
    throw ConfigError("--real-time serves the run config's plant alone: remove --config, "
                      "--protocol and --inject");
  }
  // The bench file, read once: one actuator, or `actuators: n` on one specimen.
  const EmulatedBenchSpec spec = args.config.empty()
                                     ? OneActuatorSpec(DefaultEmulatedBenchConfig())
                                     : LoadEmulatedBenchSpec(args.config);
  if (args.protocol == "ads") return ServeAds(args, spec);
  if (spec.coupled_safety && !args.inject.empty()) {
    throw ConfigError(fmt::format("{}: a bench with `actuators:` serves without --inject; "
                                  "remove --inject", args.config));
  }
  const HostPort listen = ParseHostPort(args.listen, "--listen");

  BenchServerOptions options;
  options.host = listen.host;
  options.port = listen.port;
  options.token = ServerToken(args.token);
  options.heartbeat_timeout = args.heartbeat_timeout;
  options.log = [](const std::string& line) {
    std::fprintf(stderr, "hybridtest bench: %s\n", line.c_str());
  };
  if (!args.real_time.empty()) return ServeRealTime(args, options);
  options.limits = spec.actuators[0].safety;
  for (const auto& a : spec.actuators) options.start_positions.push_back(a.initial_position);
  if (spec.coupled_safety) {
    options.actuator_stiffness = spec.stiffness;  // the coupled force prediction
  } else {
    options.initial_stiffness = spec.stiffness(0, 0);  // the specimen's initial stiffness
  }
  for (const auto& f : args.inject) options.faults.push_back(ParseFault(f, "--inject"));
  options.log = [](const std::string& line) {
    std::fprintf(stderr, "hybridtest bench: %s\n", line.c_str());
  };

  std::unique_ptr<TransferSystem> served = MakeEmulatedBench(spec);
  if (args.protocol == "openfresco") return ServeOpenFresco(args, spec, *served, options);
  TransferSystem* bench = served.get();
  BenchServer server(*bench, options);

  std::string faults;
  for (const auto& f : args.inject) faults += (faults.empty() ? "" : ",") + f;
  std::printf("hybridtest bench: listening on %s (%s; token %s%s)\n", server.address().c_str(),
              bench->Describe().c_str(), options.token.empty() ? "none" : "required",
              faults.empty() ? "" : ("; TEST FAULTS INJECTED: " + faults).c_str());
  std::fflush(stdout);
  ServeUntilSignal(server);
}

void AddBenchCommand(CLI::App& root) {
  auto args = std::make_shared<BenchArgs>();
  CLI::App* cmd = root.add_subcommand(
      "bench", "Serve the emulated test bench over TCP until SIGINT/SIGTERM: the hybridtest "
               "bench protocol (default), OpenFresco's generic TCP protocol or ADS (a TwinCAT "
               "PLC emulator), chosen by --protocol");
  cmd->add_option("--config", args->config,
                  "YAML file with a `bench:` mapping (default: the seed paper's cantilever)")
      ->check(RegularInputFile());
  CLI::Option* listen = cmd->add_option("--listen", args->listen,
                  "HOST:PORT to listen on; port 0 picks a free port (default 127.0.0.1:7471). "
                  "A non-loopback host requires a token (--token-file or HYBRIDTEST_BENCH_TOKEN)");
  AddServerTokenOptions(*cmd, args->token, "clients");
  cmd->add_option("--heartbeat-timeout", args->heartbeat_timeout,
                  "seconds without a frame after which a client is dropped and the bench holds")
      ->check(PositiveFiniteNumber());
  cmd->add_option("--inject", args->inject,
                  "TEST FACILITY ONLY: inject a fault KIND@N at the N-th command; "
                  "--protocol hybridtest: nan, spike, corrupt, stale_seq, duplicate, silence, "
                  "close; --protocol ads: fault, silence, close, ads_error, holding");
  cmd->add_option("--protocol", args->protocol,
                  "hybridtest (the hybridtest bench protocol, default) or openfresco (OpenFresco's generic "
                  "TCP protocol, for OpenSees genericClient elements; needs --config with an "
                  "`openfresco:` section; docs/openfresco.md) or ads (a TwinCAT PLC emulator "
                  "over ADS; docs/ads.md)")
      ->check(CLI::IsMember({"hybridtest", "openfresco", "ads"}));
  cmd->add_option("--route", args->routes,
                  "--protocol ads: NETID[@ADDRESS], an AmsNetId the emulated PLC serves and the "
                  "address it must come from (default: its first four numbers; repeat for several); "
                  "required off loopback, where a TwinCAT PLC serves only routed clients");
  cmd->add_option("--ams-net-id", args->ams_net_id,
                  "--protocol ads: the emulated PLC's AmsNetId (default 127.0.0.1.1.1)");
  cmd->add_option("--plc-state", args->plc_state,
                  "--protocol ads: the PLC state ReadState shows (run, or stop to rehearse a "
                  "PLC that is not running)")
      ->check(CLI::IsMember({"run", "stop"}));
  cmd->add_option("--plc-program", args->plc_program,
                  "--protocol ads: the PLC program the emulator runs: instant (after every "
                  "write; the default, and the one --inject needs) or p_hybrid (docs/ads.md's "
                  "Structured Text, every 10 ms, with its heartbeat watchdog)")
      ->check(CLI::IsMember({"instant", "p_hybrid"}));
  cmd->add_option("--watchdog", args->watchdog,
                  "--plc-program p_hybrid: seconds without a heartbeat before the PLC holds "
                  "(tWatchdog, default 2)")
      ->check(FiniteRange(0.01, 3600.0));
  cmd->add_option("--real-time", args->real_time,
                  "serve the emulated real-time plant (rt_plant) of this run config's first "
                  "physical slot on the server's own clock (docs/real-time.md)")
      ->check(RegularInputFile());
  cmd->add_option("--tick", args->tick, "with --real-time: the client's tick in seconds "
                                        "(default 0.001; 1e-5 to 1, the tick range of a "
                                        "real-time run)")
      ->check(FiniteRange(1e-5, 1.0));
  cmd->callback([args, listen] {
    args->listen_given = listen->count() > 0;
    RunBench(*args);
  });
}

const CommandRegistration kReg{"bench", &AddBenchCommand};

}  // namespace
}  // namespace hybridtest::app
