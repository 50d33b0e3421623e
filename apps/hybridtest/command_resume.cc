// hybridtest resume RUN.csv [--bench HOST:PORT] [--quiet] [--force-tolerance N]
//                           [--after-safety-stop] [--set KEY=VALUE ...]
// Continues a stopped or killed run from its last committed step (its <run>.state.json),
// appending to the same journal and stage record. On a physical slot the last committed
// command is re-imposed first and the force checked (docs/safety.md, "Resuming a run").
// Exit 0 when the run completes; 2 if it cannot be resumed; 3 if the force check refuses.
#include "command.h"
#include "cli_values.h"
#include "run_commands.h"

namespace hybridtest::app {
namespace {

void AddResumeCommand(CLI::App& root) {
  auto opt = std::make_shared<ResumeCommandOptions>();
  CLI::App* cmd = root.add_subcommand(
      "resume", "Continue a stopped or killed run from its last committed step");
  cmd->add_option("run", opt->csv, "journal CSV of the run (its sidecar and state beside it)")
      ->required()
      ->check(RegularInputFile());
  cmd->add_option("--bench", opt->bench,
                  "HOST:PORT of a bench server, for remote transfer systems");
  cmd->add_flag("--quiet", opt->quiet, "no progress output and no summary");
  cmd->add_option("--force-tolerance", opt->force_tolerance,
                  "largest |measured - committed force| [N] accepted after re-imposing the last "
                  "committed command (default: resume.force_tolerance, else the smaller of 1 % of "
                  "force_hard and K0 times the position tolerance)")
      ->check(PositiveFiniteNumber());
  cmd->add_option("--position-tolerance", opt->position_tolerance,
                  "largest |measured - committed position| [m] accepted after re-imposing the "
                  "last committed command (default: resume.position_tolerance, else a quarter "
                  "of max_increment)")
      ->check(PositiveFiniteNumber());
  cmd->add_flag("--after-safety-stop", opt->after_safety_stop,
                "resume a run that stopped on a safety limit, once its cause is fixed");
  cmd->add_option("--set", opt->set,
                  "change a limit on resume, recorded in the sidecar: "
                  "substructures.SLOT.safety.KEY=VALUE (stroke_min, stroke_max, max_increment "
                  "[m], force_soft, force_hard [N], timeout [s]) or resume.force_tolerance / "
                  "resume.position_tolerance (repeatable)");
  AddMonitorOptions(*cmd, opt->monitor);
  cmd->callback([opt] {
    CheckMonitorOptions(opt->monitor);
    CheckJournalHeader(opt->csv, "run");
    ExecuteResume(*opt);
  });
}

const CommandRegistration kCommandResumeRegistration{"resume", &AddResumeCommand};

}  // namespace
}  // namespace hybridtest::app
