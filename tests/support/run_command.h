#pragma once
// Runs a shell command line for integration tests and captures what it prints.
#include <sys/wait.h>

#include <cstdio>
#include <stdexcept>
#include <string>
#include <utility>

namespace hybridtest::testing {

// Runs `command_line` under `timeout timeout_s` (seconds) and returns its exit status (-1 if
// it did not exit normally) and its stdout, with stderr merged in if `merge_stderr`, else
// discarded.
inline std::pair<int, std::string> RunCommand(const std::string& command_line, int timeout_s = 30,
                                              bool merge_stderr = true) {
  const std::string full = "timeout " + std::to_string(timeout_s) + " " + command_line +
                           (merge_stderr ? " 2>&1" : " 2>/dev/null");
  FILE* pipe = popen(full.c_str(), "r");
  if (pipe == nullptr) throw std::runtime_error("popen failed");
  std::string output;
  char buffer[512];
  while (fgets(buffer, sizeof buffer, pipe) != nullptr) output += buffer;
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

}  // namespace hybridtest::testing
