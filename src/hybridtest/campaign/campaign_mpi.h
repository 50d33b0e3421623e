#pragma once
// The MPI dispatcher: a campaign started under `mpirun` or `srun`. Every rank reads the
// campaign file; rank 0 owns DIR (the ledger of campaign_run.h: lock, sidecar, summary,
// figures) and hands out the pending cases one at a time to whichever rank asks next (long
// cases do not stall a static split); ranks 1..N−1 run them in process and send back their
// result rows. The ranks share nothing but the output folder. With one rank, rank 0 runs the
// cases itself. A case that fails is recorded and the campaign goes on. A rank that dies ends
// the job (Open MPI's default); the sidecar names the cases that were running and on which
// rank, and rerunning the command runs them (and every other unfinished case) again.
//
// Built only when CMake finds MPI (find_package(MPI), Debian's libopenmpi-dev); otherwise
// MpiBuilt() is false and RunCampaignMpi throws ConfigError saying how to get it.
#include <string>

#include "hybridtest/campaign/campaign_run.h"

namespace hybridtest::campaign {

// True if this build has the MPI dispatcher; `MpiLibraryVersion` names the library.
bool MpiBuilt();
std::string MpiLibraryVersion();

// True if this process was started by an MPI launcher (mpirun/mpiexec of Open MPI, MPICH's
// Hydra, Slurm's srun with PMI/PMIx): the environment variables they set.
bool StartedByMpiLauncher();

// Runs the campaign file across the job's ranks (see above). Rank 0 returns the outcome and
// throws on a campaign error (the other ranks return worker_only with exit_status 2).
CampaignOutcome RunCampaignMpi(const std::string& campaign_path, const CampaignOptions& options);

}  // namespace hybridtest::campaign
