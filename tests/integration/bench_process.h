#pragma once
// Runs `hybridtest bench` (HYBRIDTEST_BINARY) as a child process on 127.0.0.1 port 0 for
// integration tests. Every wait is bounded; the destructor always reaps the child (SIGTERM,
// then SIGKILL after a grace period).
#include <cstdint>
#include <string>
#include <vector>

#include "support/listening_process.h"
#include "support/run_command.h"

namespace hybridtest::testing {

class BenchProcess {
 public:
  // Starts `hybridtest bench --listen 127.0.0.1:0 <extra_args>` with `extra_env` ("K=V")
  // added to the environment (HYBRIDTEST_BENCH_TOKEN is not inherited), and waits (≤ 30 s)
  // for its "listening on" line.
  explicit BenchProcess(const std::vector<std::string>& extra_args,
                        const std::vector<std::string>& extra_env = {})
      : process_(Args(extra_args), Env(extra_env), "listening on 127\\.0\\.0\\.1:([0-9]+) \\(",
                 "hybridtest bench") {}

  ~BenchProcess() { process_.Terminate(10.0); }

  std::uint16_t port() const { return process_.port(); }
  const std::string& first_line() const { return process_.first_line(); }
  void Signal(int signal) { process_.Signal(signal); }

  // Waits up to `timeout` [s]; returns the exit status, 128+signal if killed, or -2 if it is
  // still running.
  int WaitExit(double timeout) { return process_.WaitExit(timeout); }

 private:
  static std::vector<std::string> Args(const std::vector<std::string>& extra_args) {
    std::vector<std::string> args = {HYBRIDTEST_BINARY, "bench", "--listen", "127.0.0.1:0"};
    args.insert(args.end(), extra_args.begin(), extra_args.end());
    return args;
  }
  static std::vector<std::string> Env(const std::vector<std::string>& extra_env) {
    std::vector<std::string> env;
    for (const auto& e : test_support::CurrentEnvironment()) {
      if (e.rfind("HYBRIDTEST_BENCH_TOKEN=", 0) != 0) env.push_back(e);
    }
    env.insert(env.end(), extra_env.begin(), extra_env.end());
    return env;
  }

  test_support::ListeningProcess process_;
};

}  // namespace hybridtest::testing
