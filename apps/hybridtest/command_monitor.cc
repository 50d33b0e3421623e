// hybridtest monitor RUN.csv [--listen HOST:PORT] [--interval S]
// Serves the monitor's page for a run started elsewhere, read-only, from its journal, sidecar
// and stage record (monitor/run_follower.h): live while the run goes on, whole once it has
// finished. Prints "hybridtest monitor: serving RUN.csv at http://HOST:PORT/" on stdout, then
// serves until SIGINT or SIGTERM. docs/monitor.md.
#include <fmt/core.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <thread>

#include "cli_values.h"
#include "command.h"
#include "hybridtest/common/error.h"
#include "hybridtest/monitor/monitor_server.h"
#include "hybridtest/transfer/auth.h"
#include "hybridtest/monitor/run_follower.h"
#include "hybridtest/transfer/socket.h"

namespace hybridtest::app {
namespace {

struct MonitorArgs {
  std::string csv;
  std::string listen = "127.0.0.1:8080";
  double interval = 0.5;
};

std::atomic<bool> g_stop{false};

extern "C" void StopMonitorOnSignal(int /*signal*/) { g_stop.store(true); }

void ServeFollower(const MonitorArgs& args) {
  const transfer::HostPort listen = transfer::ParseHostPort(args.listen, "--listen");
  monitor::MonitorState state;
  monitor::RunFollower follower(args.csv, state);
  follower.Poll();
  monitor::MonitorServerOptions options;
  options.host = listen.host;
  options.port = listen.port;
  // Read-only: no action is served, so no token guards one; off loopback the bench's rule
  // still holds (a token of 16 bytes), so that a run's data are not served to the network
  // by a typo.
  options.token = transfer::TokenFromEnvironment();
  monitor::MonitorServer server(state, nullptr, options);
  server.Start();
  std::printf("hybridtest monitor: serving %s at %s\n", args.csv.c_str(), server.url().c_str());
  std::fflush(stdout);
  struct sigaction action {};
  action.sa_handler = StopMonitorOnSignal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  auto next = std::chrono::steady_clock::now();
  while (!g_stop.load()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    if (std::chrono::steady_clock::now() < next) continue;
    next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(args.interval));
    try {
      follower.Poll();
    } catch (const Error& e) {
      std::fprintf(stderr, "hybridtest monitor: %s\n", e.what());  // shown again next time
    }
  }
  server.Stop();
}

void AddMonitorCommand(CLI::App& root) {
  auto args = std::make_shared<MonitorArgs>();
  CLI::App* cmd = root.add_subcommand(
      "monitor", "Serve the live monitor's page for a run started elsewhere (read-only), or "
                 "for a finished run");
  cmd->add_option("run", args->csv, "journal CSV of the run (its .meta.json beside it)")
      ->required()
      ->check(RegularInputFile());
  cmd->add_option("--listen", args->listen, "HOST:PORT to serve on (port 0 picks a free one)")
      ->capture_default_str();
  cmd->add_option("--interval", args->interval, "how often the files are read again [s]")
      ->capture_default_str()
      ->check(FiniteRange(0.05, 60.0));
  cmd->callback([args] {
    CheckJournalHeader(args->csv, "run");
    ServeFollower(*args);
  });
}

const CommandRegistration kCommandMonitorRegistration{"monitor", &AddMonitorCommand};

}  // namespace
}  // namespace hybridtest::app
