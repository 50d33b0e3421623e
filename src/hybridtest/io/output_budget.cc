// See output_budget.h.
#include "hybridtest/io/output_budget.h"

#include "hybridtest/common/disk_room.h"

namespace hybridtest::io {

std::uintmax_t EstimateOutputBytes(long steps, int journal_channels, int stages,
                                   int stage_channels) {
  // In double: the counts are range-checked by the config, but their product may be large.
  const double rows = static_cast<double>(steps) + 1.0;
  const double journal = rows * (journal_channels > 0 ? journal_channels : 0);
  const double stage_rows = static_cast<double>(steps) * (stages > 0 ? stages : 0);
  const double record = stage_rows * (stage_channels > 0 ? stage_channels : 0);
  const double bytes = (journal + record) * static_cast<double>(kBytesPerValue);
  constexpr double kMax = 1.8e19;  // below the largest uintmax_t
  return bytes >= kMax ? static_cast<std::uintmax_t>(kMax) : static_cast<std::uintmax_t>(bytes);
}

void CheckOutputFits(const std::string& output_path, std::uintmax_t bytes) {
  CheckFitsOnDisk(output_path, bytes, "this run", " (journal and stage record)",
                  "shorten the duration, enlarge dt, or write elsewhere with --out");
}

}  // namespace hybridtest::io
