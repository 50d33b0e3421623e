#pragma once
// A Modbus/TCP controller in a child process for tests and benchmarks: the pymodbus one
// (tests/transfer/modbus_server.py, HYBRIDTEST_MODBUS_PY) or the libmodbus one
// (bench/modbus/modbus_bench_server.cc, HYBRIDTEST_MODBUS_SERVER). Both listen on 127.0.0.1
// port 0 and print "... listening on 127.0.0.1:PORT"; the constructor waits (≤ 30 s) for that
// line. The destructor kills (SIGKILL) and reaps the child. Every wait is bounded.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <regex>
#include <stdexcept>
#include <string>
#include <vector>

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

  explicit ModbusServerProcess(std::vector<std::string> args) {
    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0) throw std::runtime_error("pipe failed");
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_ = fork();
    if (pid_ == 0) {
      dup2(fds[1], STDOUT_FILENO);
      execv(argv[0], argv.data());
      _exit(127);
    }
    close(fds[1]);
    stdout_fd_ = fds[0];
    const std::string line = ReadLine(30.0);
    std::smatch m;
    if (!std::regex_search(line, m, std::regex("listening on 127\\.0\\.0\\.1:([0-9]+)"))) {
      Kill();
      close(stdout_fd_);
      throw std::runtime_error("the Modbus server " + args[0] + " did not announce its port; "
                               "got: '" + line + "'");
    }
    port_ = static_cast<std::uint16_t>(std::stoi(m[1].str()));
  }
  ModbusServerProcess(ModbusServerProcess&& o) noexcept
      : pid_(o.pid_), stdout_fd_(o.stdout_fd_), port_(o.port_) {
    o.pid_ = -1;
    o.stdout_fd_ = -1;
  }
  ModbusServerProcess(const ModbusServerProcess&) = delete;
  ModbusServerProcess& operator=(const ModbusServerProcess&) = delete;
  ~ModbusServerProcess() {
    Kill();
    if (stdout_fd_ >= 0) close(stdout_fd_);
  }

  std::uint16_t port() const { return port_; }
  std::string address() const { return "127.0.0.1:" + std::to_string(port_); }
  // SIGKILL and reap (idempotent): the controller disappears mid-test.
  void Kill() {
    if (pid_ <= 0) return;
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
    pid_ = -1;
  }

 private:
  std::string ReadLine(double timeout) {
    std::string line;
    const auto deadline =
        std::chrono::steady_clock::now() + std::chrono::milliseconds(long(timeout * 1e3));
    while (std::chrono::steady_clock::now() < deadline) {
      pollfd pfd{stdout_fd_, POLLIN, 0};
      if (poll(&pfd, 1, 100) <= 0) continue;
      char c = 0;
      if (read(stdout_fd_, &c, 1) != 1) break;
      if (c == '\n') return line;
      line += c;
    }
    return line;
  }

  pid_t pid_ = -1;
  int stdout_fd_ = -1;
  std::uint16_t port_ = 0;
};

}  // namespace hybridtest::testing
