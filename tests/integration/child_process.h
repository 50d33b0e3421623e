#pragma once
// A child process for integration tests: runs a command with stdout and stderr going to a
// file; the destructor kills (SIGKILL) and reaps it if it is still running. Every wait is
// bounded.
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "support/listening_process.h"
#include "support/temp_dir.h"

namespace hybridtest {

using test_support::ReadText;

// A child process with stdout and stderr going to a file. The destructor kills and reaps it.
class Child {
 public:
  Child(std::vector<std::string> args, const std::filesystem::path& output) : output_(output) {
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    const int fd = ::open(output.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) throw std::runtime_error("cannot open " + output.string());
    pid_ = ::fork();
    if (pid_ == 0) {
      ::dup2(fd, STDOUT_FILENO);
      ::dup2(fd, STDERR_FILENO);
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
    ::close(fd);
  }
  ~Child() {
    if (pid_ > 0 && !exited_) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  // Exit status, 128+signal, or -2 if still running after `timeout` seconds (see
  // WaitExitBounded); once it has ended, the same status on every call.
  int WaitExit(double timeout) {
    if (exited_) return status_;
    status_ = test_support::WaitExitBounded(pid_, timeout);
    exited_ = status_ != -2;
    return status_;
  }
  std::string output() const { return ReadText(output_); }
  // Sends `signal` (e.g. SIGKILL) to the child.
  void Signal(int signal) const {
    if (!exited_) ::kill(pid_, signal);
  }

 private:
  std::filesystem::path output_;
  pid_t pid_ = -1;
  bool exited_ = false;
  int status_ = -2;
};


}  // namespace hybridtest
