#pragma once
// Self-registration of CLI subcommands. A command file command_name.cc defines
//   const hybridtest::app::CommandRegistration kCommandNameRegistration{"name", &AddNameCommand};
// (a name of its own: the executable is a unity build, several command files per translation
// unit; cmake/HybridtestUnity.cmake)
// where AddNameCommand(CLI::App& root) adds the subcommand and its callback. Callbacks report
// failures by throwing hybridtest::Error; main() turns them into a message and an exit status.
#include <CLI/CLI.hpp>

#include <functional>
#include <string>
#include <vector>

namespace hybridtest::app {

using AddCommandFn = void (*)(CLI::App& root);

struct CommandRegistration {
  CommandRegistration(std::string name, AddCommandFn add);
};

// All registered commands, sorted by name so that --help lists them in a stable order.
std::vector<std::pair<std::string, AddCommandFn>> RegisteredCommands();

// Exit status a command asks main() to return (0 unless set). A command that completes but
// must report failure (for example a run that ended in a safety stop after writing its
// results) sets it instead of calling exit().
void SetExitStatus(int status);
int exit_status();

// The process's command line as typed (argv joined with spaces), for the records.
void SetCommandLine(int argc, char** argv);
const std::string& command_line();

// What to do next after a failure, printed by main() below the error (e.g. how to resume).
void SetErrorHint(std::string hint);
const std::string& error_hint();

}  // namespace hybridtest::app
