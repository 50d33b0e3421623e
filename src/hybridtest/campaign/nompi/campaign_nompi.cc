// The build without MPI: campaign_mpi.h's functions say so.
#include <fmt/core.h>

#include "hybridtest/campaign/campaign_mpi.h"
#include "hybridtest/common/error.h"

namespace hybridtest::campaign {

bool MpiBuilt() { return false; }
std::string MpiLibraryVersion() { return "none (built without MPI)"; }

CampaignOutcome RunCampaignMpi(const std::string& campaign_path, const CampaignOptions&) {
  throw ConfigError(fmt::format(
      "{}: this hybridtest was built without MPI; install Debian's libopenmpi-dev and "
      "openmpi-bin (scripts/install-deps.sh) and build again, or run the campaign with local "
      "workers (--workers N)", campaign_path));
}

}  // namespace hybridtest::campaign
