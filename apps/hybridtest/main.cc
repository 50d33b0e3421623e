// hybridtest: the command-line front end. Thin by design: parse, hand over to the libraries,
// and turn their exceptions into a message on stderr and a non-zero exit status.
#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <yaml-cpp/exceptions.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <mutex>
#include <new>

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

namespace {
std::string& ErrorHint() {
  static std::string hint;
  return hint;
}
}  // namespace
void SetErrorHint(std::string hint) { ErrorHint() = std::move(hint); }

namespace {
std::string& CommandLineText() {
  static std::string text;
  return text;
}
}  // namespace
void SetCommandLine(int argc, char** argv) {
  std::string& text = CommandLineText();
  text.clear();
  for (int i = 0; i < argc; ++i) text += (i > 0 ? " " : "") + std::string(argv[i]);
}
const std::string& command_line() { return CommandLineText(); }
const std::string& error_hint() { return ErrorHint(); }

}  // namespace hybridtest::app

int main(int argc, char** argv) {
  using namespace hybridtest;
  CLI::App root{"hybridtest: hybrid testing of mechanical components (Kane multibody models, "
                "Runge-Kutta integration, physical and numerical substructures)"};
  root.set_version_flag("--version", std::string("hybridtest ") + kVersion);
  root.require_subcommand(1);
  root.footer(
      "Exit status: 0 success; 1 error; 2 configuration or command-line error; 3 safety stop (a limit was "
      "reached, the bench holds); 4 transfer system error (bench lost, timeout, corrupted "
      "frame); 70 internal error; 130 interrupted (Ctrl-C or SIGTERM: the run stops after the "
      "current step, everything committed is written).");
  for (const auto& [name, add] : app::RegisteredCommands()) add(root);
  app::SetCommandLine(argc, argv);

  try {
    root.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // CLI11's own codes (105, 106, ...) are mapped to the documented one: 2 for a bad
    // argument; --help and --version keep 0.
    const int status = root.exit(e);
    return status == 0 ? 0 : 2;
  } catch (const ConfigError& e) {
    std::fprintf(stderr, "hybridtest: configuration error: %s\n", e.what());
    return 2;
  } catch (const runner::Interrupted& e) {
    std::fprintf(stderr, "hybridtest: %s\n%s", e.what(), app::error_hint().c_str());
    return 130;
  } catch (const transfer::SafetyStop& e) {
    // what() starts with "safety stop:"
    std::fprintf(stderr, "hybridtest: %s\n%s", e.what(), app::error_hint().c_str());
    return 3;
  } catch (const TransferError& e) {
    std::fprintf(stderr, "hybridtest: transfer system error: %s\n%s", e.what(),
                 app::error_hint().c_str());
    return 4;
  } catch (const Error& e) {
    std::fprintf(stderr, "hybridtest: error: %s\n%s", e.what(), app::error_hint().c_str());
    return 1;
  } catch (const YAML::Exception& e) {
    // A YAML type error the config readers did not catch themselves: still the user's input.
    std::fprintf(stderr, "hybridtest: configuration error: line %d, column %d: %s\n",
                 e.mark.line + 1, e.mark.column + 1, e.msg.c_str());
    return 2;
  } catch (const std::filesystem::filesystem_error& e) {
    std::fprintf(stderr, "hybridtest: error: %s\n", e.what());  // a folder or file we cannot make
    return 1;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "hybridtest: out of memory: an input asked for more memory than this "
                 "machine has; look for a size in the inputs of this command far beyond what it "
                 "needs\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hybridtest: internal error: %s\n", e.what());
    return 70;
  }
  return app::exit_status();
}
