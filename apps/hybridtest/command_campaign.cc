// hybridtest campaign CAMPAIGN.yaml --out DIR [--workers N] [--quiet]
// Many runs of one base config (a grid, a table, seeds), each case a simulate, a run on an
// in-process bench or a plan, on local worker threads or, started under mpirun/srun, across
// MPI ranks (docs/campaigns.md). Rerunning the command finishes what is missing.
#include <fmt/core.h>

#include <cstdio>
#include <filesystem>
#include <mutex>

#include <unistd.h>

#include "command.h"
#include "hybridtest/campaign/campaign_mpi.h"
#include "hybridtest/campaign/campaign_run.h"
#include "hybridtest/common/error.h"
#include "hybridtest/common/version.h"

namespace hybridtest::app {
namespace {

struct CampaignCommandOptions {
  std::string campaign;
  std::string out;
  int workers = 0;
  bool quiet = false;
};

std::string Host() {
  char host[256] = {};
  if (::gethostname(host, sizeof host - 1) != 0) host[0] = '\0';
  return host;
}

nlohmann::json Software() {
  return {{"name", "hybridtest"}, {"version", kVersion}, {"git", kGitDescribe},
          {"build_type", kBuildType}, {"mpi", campaign::MpiLibraryVersion()}};
}

void ExecuteCampaign(const CampaignCommandOptions& opt) {
  campaign::CampaignOptions options;
  options.out_dir = opt.out;
  options.workers = opt.workers;
  // Each case's provenance is the front door's (runner/open_run.h), with the MPI library.
  options.hooks.command_line = command_line();
  options.hooks.provenance = {{"software", Software()}};
  std::error_code ec;
  options.provenance = {{"software", Software()}, {"host", Host()},
                        {"command_line", command_line()},
                        {"working_directory", std::filesystem::current_path(ec).string()}};
  auto print_mutex = std::make_shared<std::mutex>();
  if (!opt.quiet) {
    options.print = [print_mutex](const std::string& line) {
      std::scoped_lock lock(*print_mutex);
      fmt::print("{}\n", line);
      std::fflush(stdout);
    };
  }
  campaign::CampaignOutcome outcome;
  if (campaign::StartedByMpiLauncher()) {
    outcome = campaign::RunCampaignMpi(opt.campaign, options);
  } else {
    const campaign::Campaign c = campaign::LoadCampaign(opt.campaign);
    if (!opt.quiet) {
      fmt::print("hybridtest campaign {}: {} {} cases -> {} ({} workers)\n", opt.campaign,
                 c.cases.size(), campaign::CaseCommandName(c.command), opt.out,
                 opt.workers > 0 ? opt.workers : campaign::DefaultWorkers());
      std::fflush(stdout);
    }
    outcome = campaign::RunCampaignLocal(c, options);
  }
  SetExitStatus(outcome.exit_status);
  if (outcome.worker_only) return;
  fmt::print("hybridtest campaign: {} cases (ran {}, skipped {} done before): {} finished, {} "
             "failed -> {}/summary.csv\n", outcome.total, outcome.ran, outcome.skipped,
             outcome.finished, outcome.failed, opt.out);
  if (!outcome.figures.empty()) {
    fmt::print("  {} figures in {}/figures\n", outcome.figures.size(), opt.out);
  } else if (!outcome.figures_note.empty()) {
    fmt::print("  no figures: {}\n", outcome.figures_note);
  }
  if (outcome.failed > 0) {
    fmt::print("  the failed cases' errors are in summary.csv and cases/<id>/case.json; to run "
               "one again, move its folder out of {}/cases and rerun this command\n", opt.out);
  }
}

void AddCampaignCommand(CLI::App& root) {
  auto opt = std::make_shared<CampaignCommandOptions>();
  CLI::App* cmd = root.add_subcommand(
      "campaign",
      fmt::format("Run many cases of one base config (grid, table, seeds) on local workers or, "
                  "under mpirun/srun, across MPI ranks; rerun to finish what is missing. MPI: "
                  "{}", campaign::MpiBuilt() ? "built with " + campaign::MpiLibraryVersion()
                                             : std::string("not built (local workers only)")));
  cmd->add_option("campaign", opt->campaign, "campaign file (YAML, docs/campaigns.md)")
      ->required();
  cmd->add_option("--out", opt->out, "the campaign's folder: cases/<id>/, summary.csv, "
                                     "campaign.json, figures/")->required();
  cmd->add_option("--workers", opt->workers,
                  "local worker threads (default: the machine's cores); ignored under MPI")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--quiet", opt->quiet, "no progress lines");
  cmd->callback([opt] { ExecuteCampaign(*opt); });
}

const CommandRegistration kCommandCampaignRegistration{"campaign", &AddCampaignCommand};

}  // namespace
}  // namespace hybridtest::app
