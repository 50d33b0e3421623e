#pragma once
// Runs `hybridtest bench` (HYBRIDTEST_BINARY) as a child process on 127.0.0.1 port 0 for
// integration tests. Every wait is bounded; the destructor always reaps the child (SIGTERM,
// then SIGKILL after a grace period).
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
#include <thread>
#include <vector>

namespace hybridtest::testing {

class BenchProcess {
 public:
  // Starts `hybridtest bench --listen 127.0.0.1:0 <extra_args>` with `extra_env` ("K=V")
  // added to the environment, and waits (≤ 30 s) for its "listening on" line.
  explicit BenchProcess(const std::vector<std::string>& extra_args,
                        const std::vector<std::string>& extra_env = {}) {
    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0) throw std::runtime_error("pipe failed");
    std::vector<std::string> args = {HYBRIDTEST_BINARY, "bench", "--listen", "127.0.0.1:0"};
    args.insert(args.end(), extra_args.begin(), extra_args.end());
    std::vector<std::string> env;
    for (char** e = environ; *e != nullptr; ++e) {
      if (std::string(*e).rfind("HYBRIDTEST_BENCH_TOKEN=", 0) != 0) env.emplace_back(*e);
    }
    env.insert(env.end(), extra_env.begin(), extra_env.end());
    std::vector<char*> argv, envp;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    for (auto& e : env) envp.push_back(e.data());
    envp.push_back(nullptr);
    pid_ = fork();
    if (pid_ == 0) {
      dup2(fds[1], STDOUT_FILENO);
      execve(argv[0], argv.data(), envp.data());
      _exit(127);
    }
    close(fds[1]);
    stdout_fd_ = fds[0];
    const std::string line = ReadLine(30.0);
    std::smatch m;
    if (!std::regex_search(line, m, std::regex("listening on 127\\.0\\.0\\.1:([0-9]+) \\("))) {
      kill(pid_, SIGKILL);  // the destructor will not run: reap the child here
      waitpid(pid_, nullptr, 0);
      close(stdout_fd_);
      throw std::runtime_error("hybridtest bench did not announce its port; got: '" + line + "'");
    }
    port_ = static_cast<std::uint16_t>(std::stoi(m[1].str()));
    first_line_ = line;
  }

  ~BenchProcess() {
    if (pid_ > 0 && !exited_) {
      kill(pid_, SIGTERM);
      if (WaitExit(10.0) == -2) {
        kill(pid_, SIGKILL);
        waitpid(pid_, nullptr, 0);
      }
    }
    if (stdout_fd_ >= 0) close(stdout_fd_);
  }

  std::uint16_t port() const { return port_; }
  const std::string& first_line() const { return first_line_; }
  void Signal(int signal) { kill(pid_, signal); }

  // Waits up to `timeout` [s]; returns the exit status, 128+signal if killed, or -2 if it is
  // still running.
  int WaitExit(double timeout) {
    const auto deadline =
        std::chrono::steady_clock::now() + std::chrono::milliseconds(long(timeout * 1e3));
    while (std::chrono::steady_clock::now() < deadline) {
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        exited_ = true;
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return -2;
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
  bool exited_ = false;
  std::uint16_t port_ = 0;
  std::string first_line_;
};

// Runs a shell command line (bounded by `timeout_s` seconds) and returns its exit status and
// its combined stdout and stderr.
inline std::pair<int, std::string> RunCommand(const std::string& command_line, int timeout_s = 30) {
  const std::string full = "timeout " + std::to_string(timeout_s) + " " + command_line + " 2>&1";
  FILE* pipe = popen(full.c_str(), "r");
  if (pipe == nullptr) throw std::runtime_error("popen failed");
  std::string output;
  char buffer[512];
  while (fgets(buffer, sizeof buffer, pipe) != nullptr) output += buffer;
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

}  // namespace hybridtest::testing
