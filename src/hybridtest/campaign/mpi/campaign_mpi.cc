// See campaign_mpi.h. Messages between the ranks (MPI_COMM_WORLD):
//   worker → 0   kReady  (empty)            once, when the worker can take a case
//   worker → 0   kResult (CaseResult JSON)  after each case; asks for the next one too
//   0 → worker   kWork   (int)              the index of the next case, or −1: no more
#include <fmt/core.h>
#include <mpi.h>

#include <chrono>
#include <deque>
#include <exception>
#include <optional>
#include <string>
#include <thread>

#include <unistd.h>

#include "hybridtest/campaign/campaign_mpi.h"
#include "hybridtest/common/error.h"

namespace hybridtest::campaign {
namespace {

constexpr int kReady = 1;
constexpr int kResult = 2;
constexpr int kWork = 3;

class MpiEnvironment {
 public:
  MpiEnvironment() {
    int initialized = 0;
    MPI_Initialized(&initialized);
    if (!initialized) MPI_Init(nullptr, nullptr);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
  }
  ~MpiEnvironment() {
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (!finalized) MPI_Finalize();
  }
  MpiEnvironment(const MpiEnvironment&) = delete;
  MpiEnvironment& operator=(const MpiEnvironment&) = delete;
  int rank() const { return rank_; }
  int size() const { return size_; }

 private:
  int rank_ = 0;
  int size_ = 1;
};

std::string Host() {
  char host[256] = {};
  if (::gethostname(host, sizeof host - 1) != 0) return "?";
  return host;
}

// Rank 0: hands out the pending cases until every worker was told to stop.
void Dispatch(const MpiEnvironment& mpi, CampaignLedger& ledger) {
  std::deque<int> queue;
  for (int i : ledger.Pending()) queue.push_back(i);
  std::vector<std::string> names(static_cast<std::size_t>(mpi.size()));
  int active = mpi.size() - 1;
  while (active > 0) {
    // Open MPI's blocking probe spins a core; rank 0 mostly waits, so it polls and sleeps
    // (at most 1 ms late per result, against cases that take tens of milliseconds or more).
    MPI_Status status;
    for (int flag = 0;;) {
      MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status);
      if (flag) break;
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    int length = 0;
    MPI_Get_count(&status, MPI_CHAR, &length);
    std::string message(static_cast<std::size_t>(length), '\0');
    MPI_Recv(message.data(), length, MPI_CHAR, status.MPI_SOURCE, status.MPI_TAG,
             MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    const int source = status.MPI_SOURCE;
    if (status.MPI_TAG == kReady) {
      names.at(static_cast<std::size_t>(source)) =
          message.empty() ? fmt::format("rank {}", source) : message;
    } else if (status.MPI_TAG == kResult) {
      ledger.Finished(CaseResultFromJson(nlohmann::json::parse(message)));
    }
    int next = -1;
    if (!queue.empty()) {
      next = queue.front();
      queue.pop_front();
      ledger.Started(next, names.at(static_cast<std::size_t>(source)));
    } else {
      --active;
    }
    MPI_Send(&next, 1, MPI_INT, source, kWork, MPI_COMM_WORLD);
  }
}

// Ranks 1..N−1: ask, run, answer, until told to stop.
void Work(const MpiEnvironment& mpi, const Campaign& campaign, const CampaignOptions& options) {
  const std::string name = fmt::format("rank {}@{}", mpi.rank(), Host());
  MPI_Send(name.data(), static_cast<int>(name.size()), MPI_CHAR, 0, kReady, MPI_COMM_WORLD);
  for (;;) {
    int index = -1;
    MPI_Recv(&index, 1, MPI_INT, 0, kWork, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (index < 0) return;
    const std::string row =
        ToJson(RunCase(campaign, index, options.out_dir, options.hooks, name)).dump();
    MPI_Send(row.data(), static_cast<int>(row.size()), MPI_CHAR, 0, kResult, MPI_COMM_WORLD);
  }
}

}  // namespace

bool MpiBuilt() { return true; }

// From mpi.h, so that no MPI call is made outside a campaign (the help text names it).
std::string MpiLibraryVersion() {
#if defined(OMPI_MAJOR_VERSION)
  return fmt::format("Open MPI v{}.{}.{}", OMPI_MAJOR_VERSION, OMPI_MINOR_VERSION,
                     OMPI_RELEASE_VERSION);
#elif defined(MPICH_VERSION)
  return std::string("MPICH ") + MPICH_VERSION;
#else
  return fmt::format("MPI {}.{}", MPI_VERSION, MPI_SUBVERSION);
#endif
}

CampaignOutcome RunCampaignMpi(const std::string& campaign_path, const CampaignOptions& options) {
  const MpiEnvironment mpi;
  // Every rank reads the campaign; rank 0 also takes DIR. All go on only if all could.
  std::optional<Campaign> campaign;
  std::unique_ptr<CampaignLedger> ledger;
  std::exception_ptr error;
  try {
    campaign = LoadCampaign(campaign_path);
    if (mpi.rank() == 0) {
      ledger = std::make_unique<CampaignLedger>(
          *campaign, options, fmt::format("mpi ({} ranks, {})", mpi.size(), MpiLibraryVersion()),
          std::max(1, mpi.size() - 1));
    }
  } catch (...) {
    error = std::current_exception();
  }
  int ok = error ? 0 : 1;
  int all_ok = 0;
  MPI_Allreduce(&ok, &all_ok, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  if (!all_ok) {
    if (mpi.rank() == 0 && error) std::rethrow_exception(error);
    CampaignOutcome outcome;
    outcome.worker_only = true;
    outcome.exit_status = 2;
    return outcome;
  }
  if (mpi.rank() != 0) {
    Work(mpi, *campaign, options);
    CampaignOutcome outcome;
    outcome.worker_only = true;
    return outcome;
  }
  if (options.print) {
    options.print(fmt::format("hybridtest campaign {}: {} {} cases -> {} ({} MPI ranks: {}; {})",
                              campaign_path, campaign->cases.size(),
                              CaseCommandName(campaign->command), options.out_dir, mpi.size(),
                              mpi.size() == 1 ? "rank 0 runs the cases"
                                              : "rank 0 hands out the cases",
                              MpiLibraryVersion()));
  }
  try {
    if (mpi.size() == 1) {
      const std::string name = fmt::format("rank 0@{}", Host());
      for (int index : ledger->Pending()) {
        ledger->Started(index, name);
        ledger->Finished(RunCase(*campaign, index, options.out_dir, options.hooks, name));
      }
    } else {
      Dispatch(mpi, *ledger);
    }
    return ledger->Close();
  } catch (const std::exception& e) {
    // The workers wait for rank 0: end the job rather than leave them hanging.
    fmt::print(stderr, "error: {}\n", e.what());
    MPI_Abort(MPI_COMM_WORLD, 1);
    throw;
  }
}

}  // namespace hybridtest::campaign
