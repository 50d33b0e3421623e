#pragma once
// Cross-check of the runner's safety limits against the limits a bench announces (WELCOME),
// done once at connection.
//
// Both sets are SI. The runner's limits must lie within the bench's: stroke_min ≥ the bench's
// stroke_min, stroke_max ≤ its stroke_max, max_increment and force_hard ≤ the bench's (a
// relative tolerance of 1e-9 absorbs unit conversions). A runner limit beyond the bench's is
// at best a command the bench will refuse mid-test, and typically a unit slip: a stroke of
// ±150 typed in a field in metres (meant as mm) against a bench announcing ±0.15 m. The
// other direction is checked for the same slip: a runner limit within a factor 2 of 1/1000
// (or 1/10^6) of the bench's is refused as a unit slip (force_hard: 0.3 meant as kN against a
// bench announcing 300 N), before anything moves. The
// timeouts are not compared (the runner's is wall time per reply, the bench's lab time).
#include <string>

#include "hybridtest/transfer/safety.h"

namespace hybridtest::transfer {

// Throws ConfigError naming `where` (e.g. "substructures.r1.safety"), the runner's limit, the
// bench's (`bench_name`, e.g. "the bench at 127.0.0.1:7471") and, for a ratio near a power of
// 1000, the likely unit slip.
void CheckLimitsAgainstBench(const SafetyLimits& runner, const SafetyLimits& bench,
                             const std::string& where, const std::string& bench_name);

}  // namespace hybridtest::transfer
