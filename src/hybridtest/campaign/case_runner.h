#pragma once
// One case of a campaign, run in this process (a Session compiled from the case's config, or
// runner::PlanTest for a `plan` case). Its files, under DIR/cases/<id>/:
//
//   config.yaml        the case's complete run config (`hybridtest simulate config.yaml`
//                      reproduces the journal bit for bit)
//   run.csv, run.meta.json, run.state.json (and run.stages.csv for a `run` on a bench)
//                      the run's journal, sidecar and state, as `simulate`/`run` write them:
//                      never destroyed, resumable with `hybridtest resume`
//   case.json          the result: status, error, duration, metrics (written last, atomically:
//                      a case with a case.json is done and a rerun skips it)
//   interrupted-N/     the files of an earlier attempt that never finished (a killed campaign),
//                      moved aside before the case runs again
#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "hybridtest/campaign/campaign_file.h"
#include "hybridtest/io/config.h"
#include "hybridtest/runner/session.h"

namespace hybridtest::campaign {

struct CaseResult {
  int index = -1;
  std::string id;
  std::string status;    // "finished" or "failed"
  std::string error;     // why it failed ("" when finished)
  double duration = 0.0; // wall time of the case [s]
  // The campaign's metrics in its order (error() metrics are filled from the journals once
  // the reference has run; NaN when a metric cannot be computed).
  std::vector<double> metrics;
  // plan cases: recommendation, evaluations, error [-], lab_time [s], candidates.
  nlohmann::json plan = nlohmann::json::object();
  std::string worker;    // who ran it ("thread 2", "rank 3@host")
};
nlohmann::json ToJson(const CaseResult& r);
CaseResult CaseResultFromJson(const nlohmann::json& j);

// What the command line adds to each case's provenance (the case opens its run through the
// front door, runner/open_run.h, as `run` does: lock, output guards, disk budget, input
// record; the checks before motion, runner/pre_move_checks.h, are the Session's own; a plan
// case makes the stability one).
struct CaseHooks {
  std::string command_line{};  // how the campaign was started
  // Merged into each case's provenance, e.g. {"software": {"mpi": "..."}}.
  nlohmann::json provenance = nlohmann::json::object();
};

std::string CaseDir(const std::string& out_dir, const Campaign& campaign, int index);
std::string CaseJournal(const std::string& out_dir, const Campaign& campaign, int index);

// The recorded result of a case (its case.json), if it has one.
std::optional<CaseResult> ReadCaseResult(const std::string& out_dir, const Campaign& campaign,
                                         int index);

// Runs case `index` and writes its files. Never throws for what happens in the case: a bad
// config, a failed run or a write error is recorded as status "failed" with its message.
CaseResult RunCase(const Campaign& campaign, int index, const std::string& out_dir,
                   const CaseHooks& hooks, const std::string& worker);

}  // namespace hybridtest::campaign
