// StartedByMpiLauncher (campaign_mpi.h), in every build: a build without MPI must still see
// that it was started as one of several ranks, and refuse instead of running the campaign
// several times over.
#include <cstdlib>

#include "hybridtest/campaign/campaign_mpi.h"

namespace hybridtest::campaign {

bool StartedByMpiLauncher() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE",
                           "MPI_LOCALNRANKS"}) {
    if (std::getenv(name) != nullptr) return true;
  }
  return false;
}

}  // namespace hybridtest::campaign
