// hybridtest run CONFIG [--out FILE.csv] [--bench HOST:PORT] [--quiet] [--overwrite]
//                  [--clock virtual|wall]
// A hybrid test: physical substructures through their transfer systems, numerical ones in the
// loop. Exits non-zero on a safety stop or a lost bench, after writing every committed step.
#include "cli_values.h"
#include "command.h"
#include "run_commands.h"

namespace hybridtest::app {
namespace {

void AddRunCommand(CLI::App& root) {
  auto opt = std::make_shared<RunCommandOptions>();
  CLI::App* cmd = root.add_subcommand(
      "run", "Run a hybrid test: the model with its physical and numerical substructures");
  cmd->add_option("config", opt->config, "run configuration (YAML)")->required();
  cmd->add_option("--out", opt->out, "journal CSV (default: output.csv of the config, else "
                                     "results/<config name>.csv)");
  cmd->add_option("--bench", opt->bench,
                  "HOST:PORT of a bench server (remote) or a Modbus/TCP controller (modbus)");
  cmd->add_flag("--quiet", opt->quiet, "no progress output and no summary");
  cmd->add_flag("--overwrite", opt->overwrite,
                "replace an earlier run at the output path (refused without it: exit 2)");
  cmd->add_option("--clock", opt->clock, "a real-time config's clock: wall (default, paced) or "
                                       "virtual (simulated time, no sleeping, reproducible)")
      ->check(CLI::IsMember({"virtual", "wall"}));
  AddMonitorOptions(*cmd, opt->monitor);
  cmd->callback([opt] {
    CheckMonitorOptions(opt->monitor);
    ExecuteRun(*opt);
  });
}

const CommandRegistration kCommandRunRegistration{"run", &AddRunCommand};

}  // namespace
}  // namespace hybridtest::app
