// See server_token.h.
#include "server_token.h"

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/auth.h"

namespace hybridtest::app {

void AddServerTokenOptions(CLI::App& cmd, ServerTokenOptions& options, const std::string& who) {
  cmd.add_option("--token-file", options.file,
                 "file whose first line is the shared token " + who +
                     " must present (default: the environment variable HYBRIDTEST_BENCH_TOKEN, "
                     "if set)");
  cmd.add_option("--token", options.on_command_line,
                 "refused: visible in the process list; use --token-file")
      ->group("");
}

std::string ServerToken(const ServerTokenOptions& options) {
  if (!options.on_command_line.empty()) {
    throw ConfigError("--token: a token on the command line is visible to every user in the "
                      "process list; put it in a file and give --token-file FILE, or set "
                      "HYBRIDTEST_BENCH_TOKEN");
  }
  return options.file.empty() ? transfer::TokenFromEnvironment()
                              : transfer::ReadTokenFile(options.file, "--token-file");
}

}  // namespace hybridtest::app
