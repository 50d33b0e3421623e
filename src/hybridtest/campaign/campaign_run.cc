// See campaign_run.h.
#include "hybridtest/campaign/campaign_run.h"

#include <fmt/core.h>

#include <atomic>
#include <exception>
#include <filesystem>
#include <fstream>
#include <thread>

#include "hybridtest/campaign/summary.h"
#include "hybridtest/common/error.h"
#include "hybridtest/io/atomic_file.h"
#include "hybridtest/io/digest.h"
#include "hybridtest/io/utc_time.h"

namespace hybridtest::campaign {
namespace fs = std::filesystem;
namespace {

std::string SidecarPath(const std::string& dir) {
  return (fs::path(dir) / "campaign.json").string();
}

// Progress updates replace the sidecar atomically (a reader sees the old or the new text) but
// are not synced: the cases' case.json files are the record of truth, and a rerun rebuilds the
// progress from them. The first write of an invocation is synced (WriteFileAtomically).
void ReplaceFile(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".progress";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << text;
    out.flush();
    if (!out) throw IoError(fmt::format("{}: cannot write ({})", tmp, io::OsError()));
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) throw IoError(fmt::format("{}: cannot replace ({})", path, ec.message()));
}

}  // namespace

int DefaultWorkers() {
  const unsigned n = std::thread::hardware_concurrency();
  return n == 0 ? 1 : static_cast<int>(n);
}

CampaignLedger::CampaignLedger(const Campaign& campaign, const CampaignOptions& options,
                               std::string mode, int workers)
    : campaign_(campaign), options_(options), results_(campaign.cases.size()),
      start_(std::chrono::steady_clock::now()) {
  const std::string& dir = options.out_dir;
  if (fs::exists(dir) && !fs::is_directory(dir)) {
    throw ConfigError(fmt::format("--out {}: exists and is not a folder; give a new or an "
                                  "earlier campaign's folder", dir));
  }
  fs::create_directories(fs::path(dir) / "cases");
  lock_.emplace(io::RunLock::Acquire((fs::path(dir) / "summary.csv").string(), "campaign"));
  const std::string campaign_sha = io::Sha256Hex(campaign.text);
  const std::string base_sha = io::Sha256Hex(campaign.base_text);
  std::ifstream old(SidecarPath(dir));
  if (old) {
    try {
      sidecar_ = nlohmann::json::parse(old);
    } catch (const std::exception& e) {
      throw ConfigError(fmt::format("{}: not a campaign record ({}); give a new --out folder",
                                    SidecarPath(dir), e.what()));
    }
    using Pointer = nlohmann::json::json_pointer;
    const std::string old_campaign = sidecar_.value(Pointer("/campaign/sha256"), "");
    const std::string old_base = sidecar_.value(Pointer("/base/sha256"), "");
    if (old_campaign != campaign_sha || old_base != base_sha) {
      throw ConfigError(fmt::format(
          "{} holds the results of another campaign ({} changed since); results are never "
          "destroyed: give a new --out folder, or restore the campaign as it was",
          dir, old_campaign != campaign_sha ? "the campaign file" : "the base config"));
    }
    const nlohmann::json running =
        sidecar_.value(Pointer("/progress/running"), nlohmann::json::array());
    if (options.print && running.is_array() && !running.empty()) {
      std::string list;
      for (const auto& r : running) {
        list += fmt::format("\n    {} (on {} since {})", r.value("case", "?"),
                            r.value("worker", "?"), r.value("since", "?"));
      }
      options.print(fmt::format("the last invocation stopped while these cases ran (a killed "
                                "campaign or a dead rank); they run again:{}", list));
    }
  } else {
    sidecar_ = {{"format", "hybridtest campaign 1"},
                {"campaign", {{"path", campaign.path}, {"sha256", campaign_sha},
                              {"text", campaign.text}}},
                {"base", {{"path", campaign.base_path}, {"sha256", base_sha},
                          {"text", campaign.base_text}}},
                {"command", CaseCommandName(campaign.command)},
                {"cases", campaign.cases.size()},
                {"invocations", nlohmann::json::array()}};
  }
  for (std::size_t i = 0; i < campaign.cases.size(); ++i) {
    results_[i] = ReadCaseResult(dir, campaign, static_cast<int>(i));
    if (results_[i]) ++outcome_.skipped;
  }
  outcome_.total = static_cast<int>(campaign.cases.size());
  nlohmann::json invocation = options.provenance;
  invocation["started"] = io::UtcNowIso8601();
  invocation["mode"] = mode;
  invocation["workers"] = workers;
  invocation["skipped"] = outcome_.skipped;
  invocation["ran"] = nlohmann::json::array();
  sidecar_["invocations"].push_back(invocation);
  std::scoped_lock lock(mutex_);
  WriteSidecar();
}

CampaignLedger::~CampaignLedger() = default;

std::vector<int> CampaignLedger::Pending() const {
  std::vector<int> pending;
  for (std::size_t i = 0; i < results_.size(); ++i) {
    if (!results_[i]) pending.push_back(static_cast<int>(i));
  }
  return pending;
}

void CampaignLedger::Started(int index, const std::string& worker) {
  std::scoped_lock lock(mutex_);
  running_.emplace_back(index, worker);
  running_since_.push_back(io::UtcNowIso8601());
  WriteSidecar();
}

void CampaignLedger::Finished(const CaseResult& result) {
  std::scoped_lock lock(mutex_);
  for (std::size_t k = 0; k < running_.size(); ++k) {
    if (running_[k].first == result.index) {
      running_.erase(running_.begin() + static_cast<std::ptrdiff_t>(k));
      running_since_.erase(running_since_.begin() + static_cast<std::ptrdiff_t>(k));
      break;
    }
  }
  results_.at(result.index) = result;
  ++outcome_.ran;
  outcome_.ran_ids.push_back(result.id);
  sidecar_["invocations"].back()["ran"].push_back(result.id);
  WriteSidecar();
  if (options_.print) {
    const auto& p = sidecar_["progress"];
    options_.print(fmt::format("[{}/{}] {} {} in {:.2f} s on {}{}  (failed {}, ETA {:.0f} s)",
                               p["done"].get<int>(), outcome_.total, result.id, result.status,
                               result.duration, result.worker,
                               result.error.empty() ? "" : ": " + result.error,
                               p["failed"].get<int>(), p["eta_s"].get<double>()));
  }
}

void CampaignLedger::WriteSidecar() {
  int done = 0, failed = 0;
  for (const auto& r : results_) {
    if (!r) continue;
    ++done;
    if (r->status != "finished") ++failed;
  }
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const int left = outcome_.total - done;
  const double eta = outcome_.ran > 0 ? elapsed / outcome_.ran * left : 0.0;
  nlohmann::json running = nlohmann::json::array();
  for (std::size_t k = 0; k < running_.size(); ++k) {
    running.push_back({{"case", campaign_.cases.at(running_[k].first).id},
                       {"worker", running_[k].second}, {"since", running_since_[k]}});
  }
  sidecar_["progress"] = {{"total", outcome_.total}, {"done", done}, {"failed", failed},
                          {"pending", left}, {"running", running},
                          {"elapsed_s", elapsed}, {"eta_s", eta},
                          {"updated", io::UtcNowIso8601()}};
  sidecar_["status"] = left == 0 ? (failed > 0 ? "completed with failures" : "completed")
                                 : "running";
  if (synced_) {
    ReplaceFile(SidecarPath(options_.out_dir), sidecar_.dump(2) + "\n");
  } else {
    io::WriteFileAtomically(SidecarPath(options_.out_dir), sidecar_.dump(2) + "\n");
    synced_ = true;
  }
}

CampaignOutcome CampaignLedger::Close() {
  std::scoped_lock lock(mutex_);
  FillErrorMetrics(campaign_, options_.out_dir, results_);
  for (const auto& r : results_) {
    if (r && r->status == "finished") ++outcome_.finished;
    if (r && r->status != "finished") ++outcome_.failed;
  }
  io::WriteFileAtomically((fs::path(options_.out_dir) / "summary.csv").string(),
                          SummaryCsv(campaign_, results_));
  if (campaign_.figures) {
    try {
      outcome_.figures = WriteCampaignFigures(campaign_, results_, options_.out_dir);
    } catch (const std::exception& e) {
      outcome_.figures_note = e.what();
    }
  }
  sidecar_["invocations"].back()["finished"] = io::UtcNowIso8601();
  if (!outcome_.figures_note.empty()) sidecar_["figures_note"] = outcome_.figures_note;
  synced_ = false;
  WriteSidecar();
  outcome_.exit_status = outcome_.failed > 0 || outcome_.finished < outcome_.total ? 1 : 0;
  return outcome_;
}

CampaignOutcome RunCampaignLocal(const Campaign& campaign, const CampaignOptions& options) {
  const int workers = options.workers > 0 ? options.workers : DefaultWorkers();
  CampaignLedger ledger(campaign, options, "local", workers);
  const std::vector<int> pending = ledger.Pending();
  std::atomic<std::size_t> next{0};
  std::mutex error_mutex;
  std::exception_ptr error;  // a ledger failure (the sidecar cannot be written): stop handing out
  auto work = [&](int w) {
    const std::string name = fmt::format("thread {}", w);
    try {
      for (std::size_t k = next++; k < pending.size(); k = next++) {
        ledger.Started(pending[k], name);
        ledger.Finished(RunCase(campaign, pending[k], options.out_dir, options.hooks, name));
      }
    } catch (...) {
      next = pending.size();
      std::scoped_lock lock(error_mutex);
      if (!error) error = std::current_exception();
    }
  };
  const int threads = std::max(1, std::min<int>(workers, static_cast<int>(pending.size())));
  if (threads == 1) {
    work(0);
  } else {
    std::vector<std::thread> pool;
    for (int w = 0; w < threads; ++w) pool.emplace_back(work, w);
    for (auto& t : pool) t.join();
  }
  if (error) std::rethrow_exception(error);
  return ledger.Close();
}

}  // namespace hybridtest::campaign
