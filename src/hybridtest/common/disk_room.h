#pragma once
// The one check that what is about to be written fits on its disk, made before anything is
// written: a run's journal and stage record (io/output_budget.h, CheckOutputFits) and a
// site's journal up to its bound (transfer/site/site_server.h) are refused at once, with the
// numbers and the fix, instead of filling the disk hours later.
#include <cstdint>
#include <string>
#include <string_view>

namespace hybridtest {

inline constexpr std::uintmax_t kDiskKeptFree = 64u << 20;  // left free. [bytes]

// Throws ConfigError if `bytes` plus kDiskKeptFree exceed the space available on the file
// system that will hold `path` (its nearest existing parent folder). The message reads
//   "<path>: <who> would write about <bytes, MB><detail>, but <folder> has <free, MB> free
//    (and <kDiskKeptFree, MB> are kept free); <fix>"
// Does nothing if the space cannot be queried (the writer's own errors still report a full
// disk). Unit of `bytes`: [bytes].
void CheckFitsOnDisk(const std::string& path, std::uintmax_t bytes, std::string_view who,
                     std::string_view detail, std::string_view fix);

}  // namespace hybridtest
