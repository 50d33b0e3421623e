// See live_monitor.h.
#include "live_monitor.h"

#include <fmt/core.h>

#include <chrono>
#include <cstdio>
#include <thread>

#include "cli_values.h"
#include "hybridtest/common/error.h"
#include "hybridtest/monitor/monitor_observer.h"
#include "hybridtest/monitor/monitor_server.h"
#include "hybridtest/monitor/operator_control.h"
#include "hybridtest/transfer/auth.h"
#include "hybridtest/transfer/socket.h"

namespace hybridtest::app {

void AddMonitorOptions(CLI::App& cmd, MonitorCliOptions& options) {
  cmd.add_option("--monitor", options.listen,
                 "serve a live monitor (a page and an HTTP API) on HOST:PORT, e.g. "
                 "127.0.0.1:8080 (port 0 picks one; another address than loopback needs a "
                 "token of 16 bytes or more); see docs/monitor.md");
  cmd.add_option("--token-file", options.token_file,
                 "file whose first line is the token the monitor's Hold/Continue/Stop need "
                 "(else HYBRIDTEST_BENCH_TOKEN)");
  cmd.add_flag("--monitor-no-token", options.no_token,
               "let the monitor's actions through without a token (loopback only)");
  cmd.add_option("--monitor-linger", options.linger,
                 "after the run, keep serving its final state this many seconds [s]")
      ->check(CLI::Range(0.0, 86400.0));
}

struct LiveMonitor::Parts {
  monitor::MonitorState state;
  monitor::MonitorObserver observer{state};
  monitor::OperatorControl control{state};
  std::unique_ptr<monitor::MonitorServer> server;
};

LiveMonitor::LiveMonitor(const MonitorCliOptions& options, runner::Session& session)
    : parts_(std::make_unique<Parts>()), linger_(options.linger) {
  const transfer::HostPort listen = transfer::ParseHostPort(*options.listen, "--monitor");
  monitor::MonitorServerOptions server;
  server.host = listen.host;
  server.port = listen.port;
  server.token = options.token_file.empty() ? transfer::TokenFromEnvironment()
                                            : transfer::ReadTokenFile(options.token_file,
                                                                      "--token-file");
  server.actions_without_token = options.no_token;
  if (options.no_token && !transfer::IsLoopbackHost(listen.host)) {
    throw ConfigError(fmt::format("--monitor-no-token with --monitor {}: actions without a token "
                                  "are only allowed on loopback; give --token-file FILE instead",
                                  *options.listen));
  }
  // A real-time run: the server's thread takes no time from the stepping thread
  // (monitor/background_thread.h); Hold/Continue/Stop act between steps as on any run.
  const io::RealTimeSpec& rt = session.spec().real_time;
  server.background = rt.enabled;
  server.avoid_cpu = rt.cpu;
  server.log = [](const std::string& line) {
    std::fprintf(stderr, "hybridtest monitor: %s\n", line.c_str());
  };
  parts_->server = std::make_unique<monitor::MonitorServer>(parts_->state, &parts_->control,
                                                             std::move(server));
  session.AddObserver(parts_->observer);
  session.SetBetweenSteps(
      [control = &parts_->control](runner::Session& s) { return control->BetweenSteps(s); });
  parts_->server->Start();
  std::fprintf(stderr, "hybridtest: monitor at %s (actions: %s)\n", parts_->server->url().c_str(),
               options.no_token ? "no token needed" : "token required");
  std::fflush(stderr);
}

LiveMonitor::~LiveMonitor() = default;


void LiveMonitor::Linger(const runner::Session& session) {
  // The final state stays on the page for --monitor-linger seconds; Ctrl-C ends it sooner
  // (after a stop, which is a stop request already, a second Ctrl-C ends the process).
  const bool stop_before = session.stop_requested();
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(linger_);
  while (std::chrono::steady_clock::now() < until && (stop_before || !session.stop_requested())) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

}  // namespace hybridtest::app
