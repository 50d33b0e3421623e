#pragma once
// A server in a child process for tests and benchmarks: started with execve, its stdout a pipe
// to the parent, its first line read (≤ 30 s) and matched against the "listening on
// 127.0.0.1:PORT" announcement. The destructor kills (SIGKILL) and reaps the child if it is
// still running. Every wait is bounded.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <regex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace hybridtest::test_support {

// Waits up to `timeout` [s] for `pid` to end; returns its exit status, 128+signal if a signal
// ended it, or -2 if it is still running (0 s: just looks).
inline int WaitExitBounded(pid_t pid, double timeout) {
  const auto deadline =
      std::chrono::steady_clock::now() + std::chrono::milliseconds(long(timeout * 1e3));
  for (;;) {
    int status = 0;
    if (::waitpid(pid, &status, WNOHANG) == pid) {
      return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    }
    if (std::chrono::steady_clock::now() >= deadline) return -2;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

// This process's environment, "K=V" each.
inline std::vector<std::string> CurrentEnvironment() {
  std::vector<std::string> env;
  for (char** e = environ; *e != nullptr; ++e) env.emplace_back(*e);
  return env;
}

class ListeningProcess {
 public:
  // Starts args[0] with `args` and environment `env`; `announcement` is the regular
  // expression of its first line, whose group 1 is the port; `what` names the server in the
  // error thrown (after killing the child) when the line does not match.
  ListeningProcess(std::vector<std::string> args, std::vector<std::string> env,
                   const std::string& announcement, const std::string& what) {
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) throw std::runtime_error("pipe failed");
    std::vector<char*> argv, envp;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    for (auto& e : env) envp.push_back(e.data());
    envp.push_back(nullptr);
    pid_ = ::fork();
    if (pid_ == 0) {
      ::dup2(fds[1], STDOUT_FILENO);
      ::execve(argv[0], argv.data(), envp.data());
      ::_exit(127);
    }
    ::close(fds[1]);
    stdout_fd_ = fds[0];
    first_line_ = ReadLine(30.0);
    std::smatch m;
    if (!std::regex_search(first_line_, m, std::regex(announcement))) {
      Kill();
      ::close(stdout_fd_);
      throw std::runtime_error(what + " did not announce its port; got: '" + first_line_ + "'");
    }
    port_ = static_cast<std::uint16_t>(std::stoi(m[1].str()));
  }
  ListeningProcess(ListeningProcess&& o) noexcept
      : pid_(o.pid_),
        stdout_fd_(o.stdout_fd_),
        port_(o.port_),
        first_line_(std::move(o.first_line_)),
        last_status_(o.last_status_) {
    o.pid_ = -1;
    o.stdout_fd_ = -1;
  }
  ListeningProcess(const ListeningProcess&) = delete;
  ListeningProcess& operator=(const ListeningProcess&) = delete;
  ListeningProcess& operator=(ListeningProcess&&) = delete;
  ~ListeningProcess() {
    Kill();
    if (stdout_fd_ >= 0) ::close(stdout_fd_);
  }

  std::uint16_t port() const { return port_; }
  const std::string& first_line() const { return first_line_; }
  void Signal(int signal) const {
    if (pid_ > 0) ::kill(pid_, signal);
  }
  // Waits up to `timeout` [s]: exit status, 128+signal, or -2 if still running (see
  // WaitExitBounded); once it has ended, the child is reaped and forgotten.
  int WaitExit(double timeout) {
    if (pid_ <= 0) return last_status_;
    const int status = WaitExitBounded(pid_, timeout);
    if (status != -2) {
      pid_ = -1;
      last_status_ = status;
    }
    return status;
  }
  // SIGKILL and reap (idempotent).
  void Kill() {
    if (pid_ <= 0) return;
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, nullptr, 0);
    pid_ = -1;
  }
  // SIGTERM, then SIGKILL if it has not ended within `grace` [s].
  void Terminate(double grace) {
    if (pid_ <= 0) return;
    ::kill(pid_, SIGTERM);
    if (WaitExit(grace) == -2) Kill();
  }

 private:
  std::string ReadLine(double timeout) {
    std::string line;
    const auto deadline =
        std::chrono::steady_clock::now() + std::chrono::milliseconds(long(timeout * 1e3));
    while (std::chrono::steady_clock::now() < deadline) {
      pollfd pfd{stdout_fd_, POLLIN, 0};
      if (::poll(&pfd, 1, 100) <= 0) continue;
      char c = 0;
      if (::read(stdout_fd_, &c, 1) != 1) break;
      if (c == '\n') return line;
      line += c;
    }
    return line;
  }

  pid_t pid_ = -1;
  int stdout_fd_ = -1;
  std::uint16_t port_ = 0;
  std::string first_line_;
  int last_status_ = -2;
};

}  // namespace hybridtest::test_support
