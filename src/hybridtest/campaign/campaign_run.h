#pragma once
// Running a campaign: the ledger that owns DIR (its lock, the sidecar DIR/campaign.json with
// the provenance and the progress, the summary and the figures) and the local runner (worker
// threads in this process). The MPI dispatcher (campaign_mpi.h) uses the same ledger on
// rank 0.
//
// A rerun of the same campaign into the same DIR skips every case that has a case.json
// (finished or failed) and runs the others; DIR refuses a different campaign file or base
// config (their digests are in the sidecar): results are never destroyed.
#include <nlohmann/json.hpp>

#include <chrono>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "hybridtest/campaign/campaign_file.h"
#include "hybridtest/campaign/case_runner.h"
#include "hybridtest/io/run_lock.h"

namespace hybridtest::campaign {

struct CampaignOptions {
  std::string out_dir;
  int workers = 0;  // local worker threads; 0: the machine's cores
  CaseHooks hooks;
  nlohmann::json provenance = nlohmann::json::object();  // software, host, command line
  std::function<void(const std::string&)> print;         // progress lines (none if empty)
};

struct CampaignOutcome {
  int total = 0;
  int skipped = 0;   // done before this invocation
  int ran = 0;       // run by this invocation
  int finished = 0;  // all cases that finished (this and earlier invocations)
  int failed = 0;
  std::vector<std::string> ran_ids;
  std::vector<std::string> figures;  // files written
  std::string figures_note;          // why there are none, if gnuplot failed
  bool worker_only = false;          // an MPI rank other than 0: nothing to report
  int exit_status = 0;
};

class CampaignLedger {
 public:
  // Creates DIR, takes its lock, checks or writes the sidecar, reads the cases already done.
  // `mode` is "local" or "mpi"; `workers` the number of processes or threads that run cases.
  // Throws ConfigError when DIR holds another campaign or is locked by a live campaign.
  CampaignLedger(const Campaign& campaign, const CampaignOptions& options, std::string mode,
                 int workers);
  ~CampaignLedger();
  CampaignLedger(const CampaignLedger&) = delete;
  CampaignLedger& operator=(const CampaignLedger&) = delete;

  // The cases still to run, in campaign order.
  std::vector<int> Pending() const;
  // Thread-safe.
  void Started(int index, const std::string& worker);
  void Finished(const CaseResult& result);
  // The summary, the figures and the final sidecar.
  CampaignOutcome Close();

 private:
  void WriteSidecar();  // with mutex_ held

  const Campaign& campaign_;
  const CampaignOptions& options_;
  std::optional<io::RunLock> lock_;
  std::mutex mutex_;
  std::vector<std::optional<CaseResult>> results_;
  std::vector<std::pair<int, std::string>> running_;
  std::vector<std::string> running_since_;
  nlohmann::json sidecar_;
  bool synced_ = false;  // the sidecar was written durably once (then progress is not synced)
  CampaignOutcome outcome_;
  std::chrono::steady_clock::time_point start_;
};

// Runs the pending cases on options.workers threads (each case a Session of its own).
CampaignOutcome RunCampaignLocal(const Campaign& campaign, const CampaignOptions& options);

// The number of workers `0` stands for: the machine's cores (at least 1).
int DefaultWorkers();

}  // namespace hybridtest::campaign
