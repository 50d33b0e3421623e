// hybridtest: the command-line front end. Thin by design: parse, hand over to the libraries,
// and turn their exceptions into a message on stderr and a non-zero exit status.
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <mutex>

#include "command.h"
#include "hybridtest/common/error.h"
#include "hybridtest/common/version.h"
#include "hybridtest/runner/stop_request.h"
#include "hybridtest/transfer/safety.h"

namespace hybridtest::app {
namespace {
std::vector<std::pair<std::string, AddCommandFn>>& Registry() {
  static std::vector<std::pair<std::string, AddCommandFn>> registry;
  return registry;
}
int g_exit_status = 0;
}  // namespace

CommandRegistration::CommandRegistration(std::string name, AddCommandFn add) {
  Registry().emplace_back(std::move(name), add);
}

std::vector<std::pair<std::string, AddCommandFn>> RegisteredCommands() {
  auto commands = Registry();
  std::sort(commands.begin(), commands.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  return commands;
}

void SetExitStatus(int status) { g_exit_status = status; }
int exit_status() { return g_exit_status; }

}  // namespace hybridtest::app

int main(int argc, char** argv) {
  using namespace hybridtest;
  CLI::App root{"hybridtest: hybrid testing of mechanical components (Kane multibody models, "
                "Runge-Kutta integration, physical and numerical substructures)"};
  root.set_version_flag("--version", std::string("hybridtest ") + kVersion);
  root.require_subcommand(1);
  root.footer(
      "Exit status: 0 success; 1 error; 2 configuration error; 3 safety stop (a limit was "
      "reached, the bench holds); 4 transfer system error (bench lost, timeout, corrupted "
      "frame); 70 internal error; 130 interrupted (Ctrl-C or SIGTERM: the run stops after the "
      "current step, everything committed is written); other non-zero: command-line usage "
      "error.");
  for (const auto& [name, add] : app::RegisteredCommands()) add(root);

  try {
    root.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return root.exit(e);
  } catch (const ConfigError& e) {
    std::fprintf(stderr, "hybridtest: configuration error: %s\n", e.what());
    return 2;
  } catch (const runner::Interrupted& e) {
    std::fprintf(stderr, "hybridtest: %s\n", e.what());
    return 130;
  } catch (const transfer::SafetyStop& e) {
    std::fprintf(stderr, "hybridtest: %s\n", e.what());  // what() starts with "safety stop:"
    return 3;
  } catch (const TransferError& e) {
    std::fprintf(stderr, "hybridtest: transfer system error: %s\n", e.what());
    return 4;
  } catch (const Error& e) {
    std::fprintf(stderr, "hybridtest: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hybridtest: internal error: %s\n", e.what());
    return 70;
  }
  return app::exit_status();
}
