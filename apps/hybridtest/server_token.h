#pragma once
// The token of a server command (`hybridtest bench`, `hybridtest site`; docs/protocol.md §3):
// from --token-file FILE or the environment variable HYBRIDTEST_BENCH_TOKEN, never from the
// command line (a --token option is kept only to refuse it with the fix). One place, so that
// every server command reads and refuses a token alike.
#include <CLI/CLI.hpp>

#include <string>

namespace hybridtest::app {

struct ServerTokenOptions {
  std::string file;             // --token-file
  std::string on_command_line;  // --token: refused
};

// Adds --token-file (the token `who` must present: "clients", "the coordinator") and the
// hidden --token to `cmd`.
void AddServerTokenOptions(CLI::App& cmd, ServerTokenOptions& options, const std::string& who);

// The token ("" if none is given). Throws ConfigError for --token, and what ReadTokenFile
// throws for an unreadable or unsafe file.
std::string ServerToken(const ServerTokenOptions& options);

}  // namespace hybridtest::app
