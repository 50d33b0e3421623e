#pragma once
// A Modbus/TCP controller in a child process for tests and benchmarks: the pymodbus one
// (tests/transfer/modbus_server.py, HYBRIDTEST_MODBUS_PY) or the libmodbus one
// (bench/modbus/modbus_bench_server.cc, HYBRIDTEST_MODBUS_SERVER). Both listen on 127.0.0.1
// port 0 and print "... listening on 127.0.0.1:PORT"; the constructor waits (≤ 30 s) for that
// line. The destructor kills (SIGKILL) and reaps the child. Every wait is bounded.
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "support/listening_process.h"

namespace hybridtest::testing {

// True if Debian's python3 can import pymodbus's server (python3-pymodbus and its
// dependencies). Checked once.
inline bool PymodbusAvailable() {
  static const bool available = [] {
    const std::string line = std::string(HYBRIDTEST_PYTHON) +
                             " -c 'import pymodbus.server.async_io' >/dev/null 2>&1";
    return std::system(line.c_str()) == 0;
  }();
  return available;
}

inline const char* kPymodbusMissing =
    "pymodbus is not importable by " HYBRIDTEST_PYTHON
    ": install python3-pymodbus (scripts/install-deps.sh) to run the Modbus tests";

class ModbusServerProcess {
 public:
  // The pymodbus controller with `args` (see modbus_server.py --help).
  static ModbusServerProcess Pymodbus(std::vector<std::string> args) {
    args.insert(args.begin(), {HYBRIDTEST_PYTHON, HYBRIDTEST_MODBUS_PY, "--listen", "127.0.0.1:0"});
    return ModbusServerProcess(args);
  }

  explicit ModbusServerProcess(std::vector<std::string> args)
      : process_(args, test_support::CurrentEnvironment(),
                 "listening on 127\\.0\\.0\\.1:([0-9]+)", "the Modbus server " + args[0]) {}

  std::uint16_t port() const { return process_.port(); }
  std::string address() const { return "127.0.0.1:" + std::to_string(port()); }
  // SIGKILL and reap (idempotent): the controller disappears mid-test.
  void Kill() { process_.Kill(); }

 private:
  test_support::ListeningProcess process_;
};

}  // namespace hybridtest::testing
