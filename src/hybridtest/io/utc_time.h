#pragma once
// The wall-clock time of a result's records (a journal's start_time, a resume record's time):
// UTC, ISO 8601 to the second, "YYYY-MM-DDTHH:MM:SSZ" (e.g. "2026-11-23T00:34:43Z").
#include <string>

namespace hybridtest::io {

// The current UTC time as "YYYY-MM-DDTHH:MM:SSZ".
std::string UtcNowIso8601();

}  // namespace hybridtest::io
