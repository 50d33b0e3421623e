#pragma once
// The live monitor of `run` and `resume` (--monitor HOST:PORT, docs/monitor.md): the options
// both commands add, and the monitor a run carries while it steps.
#include <CLI/CLI.hpp>

#include <memory>
#include <optional>
#include <string>

#include "hybridtest/runner/session.h"

namespace hybridtest::app {

struct MonitorCliOptions {
  std::optional<std::string> listen;  // --monitor HOST:PORT
  std::string token_file;             // --token-file: the actions' bearer token
  bool no_token = false;              // --monitor-no-token: actions without a token
  double linger = 0.0;                // --monitor-linger S: serve the final state S seconds
  bool enabled() const { return listen.has_value(); }
};

// Adds --monitor, --token-file, --monitor-no-token and --monitor-linger to `cmd`.
void AddMonitorOptions(CLI::App& cmd, MonitorCliOptions& options);

class LiveMonitor {
 public:
  // Checks the options (ConfigError), binds the server, adds the monitor to `session` and its
  // operator control as the session's between-steps hook (Session::SetBetweenSteps: Hold,
  // Continue and Stop act between two steps of the session's one loop, paced or not), before
  // Initialize(); prints the page's address on stderr.
  LiveMonitor(const MonitorCliOptions& options, runner::Session& session);
  ~LiveMonitor();
  LiveMonitor(const LiveMonitor&) = delete;
  LiveMonitor& operator=(const LiveMonitor&) = delete;

  // After the run: serves the final state for --monitor-linger seconds (Ctrl-C ends it
  // sooner). The process then exits at once: the server's Stop() closes every viewer's
  // connection, whatever they do.
  void Linger(const runner::Session& session);

 private:
  struct Parts;
  std::unique_ptr<Parts> parts_;
  double linger_ = 0.0;
};

}  // namespace hybridtest::app
