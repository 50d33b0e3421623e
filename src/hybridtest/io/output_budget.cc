// See output_budget.h.
#include "hybridtest/io/output_budget.h"

#include <fmt/core.h>

#include <filesystem>
#include <system_error>

#include "hybridtest/common/error.h"

namespace hybridtest::io {
namespace {

std::string Megabytes(std::uintmax_t bytes) {
  return fmt::format("{:.1f} MB", static_cast<double>(bytes) / 1e6);
}

}  // namespace

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
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path folder = fs::absolute(fs::path(output_path), ec).parent_path();
  while (!folder.empty() && !fs::exists(folder, ec)) {
    if (folder == folder.parent_path()) break;
    folder = folder.parent_path();
  }
  const fs::space_info space = fs::space(folder, ec);
  if (ec) return;  // unknown: the writer's own errors still report a full disk
  const std::uintmax_t free = space.available;
  if (bytes <= free && free - bytes >= kOutputSafetyMargin) return;
  throw ConfigError(fmt::format(
      "{}: this run would write about {} (journal and stage record), but {} has {} free (and "
      "{} are kept free); shorten the duration, enlarge dt, or write elsewhere with --out",
      output_path, Megabytes(bytes), folder.string(), Megabytes(free),
      Megabytes(kOutputSafetyMargin)));
}

}  // namespace hybridtest::io
