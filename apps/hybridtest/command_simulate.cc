// hybridtest simulate CONFIG [--out FILE.csv] [--quiet] [--overwrite]
// The pure numerical simulation: every restoring force from a numerical substructure.
#include "command.h"
#include "run_commands.h"

namespace hybridtest::app {
namespace {

void AddSimulateCommand(CLI::App& root) {
  auto opt = std::make_shared<RunCommandOptions>();
  opt->allow_physical = false;
  opt->command = "simulate";
  CLI::App* cmd = root.add_subcommand(
      "simulate", "Run a pure numerical simulation of the configured model (no bench)");
  cmd->add_option("config", opt->config, "run configuration (YAML)")->required();
  cmd->add_option("--out", opt->out, "journal CSV (default: output.csv of the config, else "
                                     "results/<config name>.csv); a .meta.json sidecar goes beside it");
  cmd->add_flag("--quiet", opt->quiet, "no progress output and no summary");
  cmd->add_flag("--overwrite", opt->overwrite,
                "replace an earlier run at the output path (refused without it: exit 2)");
  cmd->callback([opt] { ExecuteRun(*opt); });
}

const CommandRegistration kCommandSimulateRegistration{"simulate", &AddSimulateCommand};

}  // namespace
}  // namespace hybridtest::app
