#pragma once
// A dry-run estimate of what a run writes, checked against the free space of the disk before
// the run starts: a long run that would fill the disk (`duration: 1e12` writes ~40 MB/s) is
// refused at once with the numbers, instead of failing hours later.
//
// The journal holds steps + 1 rows of `journal_channels` values; the per-stage record of
// physical exchanges (when there is one) holds steps × stages rows of `stage_channels` values.
// A value is written in at most kBytesPerValue characters (shortest round-trip decimal, a
// sign, an exponent and the separator), so the estimate is an upper bound within about 2×.
#include <cstdint>
#include <string>

#include "hybridtest/common/disk_room.h"

namespace hybridtest::io {

inline constexpr std::uintmax_t kBytesPerValue = 26;           // [bytes]
inline constexpr std::uintmax_t kOutputSafetyMargin = kDiskKeptFree;  // left free. [bytes]

// Upper estimate of the bytes a run writes. stage_channels = 0 when there is no stage record.
std::uintmax_t EstimateOutputBytes(long steps, int journal_channels, int stages,
                                   int stage_channels);

// Throws ConfigError if `bytes` plus kOutputSafetyMargin exceed the space available on the
// file system that will hold `output_path` (its nearest existing parent folder), naming the
// estimate, the free space and how to fix it. Does nothing if the space cannot be queried.
// The run's wording of the one disk check (common/disk_room.h, CheckFitsOnDisk).
void CheckOutputFits(const std::string& output_path, std::uintmax_t bytes);

}  // namespace hybridtest::io
