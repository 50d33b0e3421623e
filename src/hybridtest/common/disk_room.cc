// See disk_room.h.
#include "hybridtest/common/disk_room.h"

#include <fmt/core.h>

#include <filesystem>
#include <system_error>

#include "hybridtest/common/error.h"

namespace hybridtest {
namespace {

std::string InMegabytes(std::uintmax_t bytes) {
  return fmt::format("{:.1f} MB", static_cast<double>(bytes) / 1e6);
}

}  // namespace

void CheckFitsOnDisk(const std::string& path, std::uintmax_t bytes, std::string_view who,
                     std::string_view detail, std::string_view fix) {
  namespace fs = std::filesystem;
  std::error_code ec;
  // The nearest folder that exists: the file and its folders may be made later.
  fs::path folder = fs::absolute(fs::path(path), ec).parent_path();
  while (!folder.empty() && !fs::exists(folder, ec)) {
    if (folder == folder.parent_path()) break;
    folder = folder.parent_path();
  }
  const fs::space_info space = fs::space(folder, ec);
  if (ec) return;
  const std::uintmax_t free = space.available;
  if (bytes <= free && free - bytes >= kDiskKeptFree) return;
  throw ConfigError(fmt::format("{}: {} would write about {}{}, but {} has {} free (and {} are "
                                "kept free); {}", path, who, InMegabytes(bytes), detail,
                                folder.string(), InMegabytes(free), InMegabytes(kDiskKeptFree),
                                fix));
}

}  // namespace hybridtest
