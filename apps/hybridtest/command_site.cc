// `hybridtest site`: serves one physical site of a multi-site test (docs/multi-site.md) until
// SIGINT or SIGTERM.
//
//   hybridtest site --config SITE.yaml [--listen HOST:PORT] [--token-file FILE] [--simcor]
//
// The site's transfer system, limits, watchdog and journal come from SITE.yaml
// (io/site_config.h); the token from --token-file or HYBRIDTEST_BENCH_TOKEN, never from the
// command line. --simcor also accepts UI-SimCor's ASCII protocol on the same port (chosen per
// connection by its first byte; no token, so loopback only). Prints "hybridtest site:
// listening on HOST:PORT (...)" once it accepts connections (port 0 picks a free port), then
// logs events to stderr.
#include <fmt/core.h>

#include <cstdio>
#include <memory>
#include <string>

#include "cli_values.h"
#include "command.h"
#include "serve_until_signal.h"
#include "server_token.h"
#include "hybridtest/common/error.h"
#include "hybridtest/io/site_config.h"
#include "hybridtest/transfer/auth.h"
#include "hybridtest/transfer/site/site_server.h"
#include "hybridtest/transfer/socket.h"

namespace hybridtest::app {
namespace {

struct SiteArgs {
  std::string config;
  std::string listen = "127.0.0.1:7480";
  ServerTokenOptions token;
  bool simcor = false;
};

void RunSite(const SiteArgs& args) {
  io::SiteConfig config = io::LoadSiteConfig(args.config);
  const transfer::HostPort listen = transfer::ParseHostPort(args.listen, "--listen");
  config.server.host = listen.host;
  config.server.port = listen.port;
  config.server.token = ServerToken(args.token);
  config.server.simcor = args.simcor;
  config.server.log = [](const std::string& line) {
    std::fprintf(stderr, "hybridtest site: %s\n", line.c_str());
  };
  std::unique_ptr<transfer::TransferSystem> bench = config.transfer.make();
  transfer::site::SiteServer server(*bench, config.server);
  std::printf("hybridtest site: listening on %s (site %s; %s; token %s)\n",
              server.address().c_str(), config.server.name.c_str(), bench->Describe().c_str(),
              config.server.token.empty() ? "none" : "required");
  std::fflush(stdout);
  ServeUntilSignal(server);
}

void AddSiteCommand(CLI::App& root) {
  auto args = std::make_shared<SiteArgs>();
  CLI::App* cmd = root.add_subcommand(
      "site", "Serve one physical site of a multi-site test (docs/multi-site.md): its transfer "
              "system behind its own safety gate, journal and watchdog, until SIGINT/SIGTERM");
  cmd->add_option("--config", args->config, "SITE.yaml with a `site:` mapping")
      ->required()
      ->check(RegularInputFile());
  cmd->add_option("--listen", args->listen,
                  "HOST:PORT to listen on; port 0 picks a free port (default 127.0.0.1:7480). "
                  "A non-loopback host requires a token of at least 16 bytes");
  AddServerTokenOptions(*cmd, args->token, "the coordinator");
  cmd->add_flag("--simcor", args->simcor,
               "also accept UI-SimCor's ASCII protocol (propose / execute / get-control-point) "
               "on the same port; it has no token, so the site must run without one, on "
               "loopback (docs/multi-site.md)");
  cmd->callback([args] { RunSite(*args); });
}

const CommandRegistration kSiteCommandRegistration{"site", &AddSiteCommand};

}  // namespace
}  // namespace hybridtest::app
