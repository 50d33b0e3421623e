// See limits_check.h.
#include "hybridtest/transfer/limits_check.h"

#include <fmt/core.h>

#include <cmath>

#include "hybridtest/common/error.h"

namespace hybridtest::transfer {
namespace {

constexpr double kRelativeTolerance = 1e-9;

// " (a factor of 1000: a value in mm typed into a field in m?)" when runner/bench is close to
// 1e3 or 1e6; empty otherwise.
// True when runner/bench lies within a factor 2 of 1/1000 or 1/10^6: the runner's limit is
// far inside the bench's by what a unit slip gives (0.3 meant as kN typed into a field in N).
bool FarInsideByAUnit(double runner, double bench) {
  if (bench == 0.0 || runner == 0.0) return false;
  const double ratio = std::abs(runner / bench);
  for (const double factor : {1e-3, 1e-6}) {
    if (ratio > 0.5 * factor && ratio < 2.0 * factor) return true;
  }
  return false;
}

std::string UnitSlipHint(double runner, double bench) {
  if (bench == 0.0 || runner == 0.0) return {};
  const double ratio = std::abs(runner / bench);
  for (const double factor : {1e3, 1e6}) {
    if (ratio > 0.3 * factor && ratio < 3.0 * factor) {
      return fmt::format(" (about {:g} times the bench's: a value in mm or kN typed into a "
                         "field in m or N?)", factor);
    }
  }
  return {};
}

}  // namespace

void CheckLimitsAgainstBench(const SafetyLimits& runner, const SafetyLimits& bench,
                             const std::string& where, const std::string& bench_name) {
  struct Check {
    const char* name;
    const char* unit;
    double runner, bench;
    bool upper;  // the runner's must be ≤ the bench's (else ≥)
  };
  const Check checks[] = {
      {"stroke_min", "m", runner.stroke_min, bench.stroke_min, false},
      {"stroke_max", "m", runner.stroke_max, bench.stroke_max, true},
      {"max_increment", "m", runner.max_increment, bench.max_increment, true},
      {"force_hard", "N", runner.force_hard, bench.force_hard, true},
  };
  for (const Check& c : checks) {
    const double slack = kRelativeTolerance * std::max(std::abs(c.runner), std::abs(c.bench));
    const bool beyond = c.upper ? c.runner > c.bench + slack : c.runner < c.bench - slack;
    if (!beyond && FarInsideByAUnit(c.runner, c.bench)) {
      throw ConfigError(fmt::format(
          "{}.{} = {} {} is about 1/{:g} of the limit {} announces, {} = {} {}: a value meant in "
          "kN or mm typed into a field in N or m? The runner's limits are SI (m and N): fix "
          "{}.{}; if the specimen's limit really is that far inside the bench's, lower the "
          "bench's {} to match",
          where, c.name, c.runner, c.unit, std::abs(c.bench / c.runner) > 3e4 ? 1e6 : 1e3,
          bench_name, c.name, c.bench, c.unit, where, c.name, c.name));
    }
    if (!beyond) continue;
    throw ConfigError(fmt::format(
        "{}.{} = {} {} is beyond the limit {} announces, {} = {} {}{}; the runner's limits "
        "must lie within the bench's: check the units (SI: m and N) and fix {}.{}",
        where, c.name, c.runner, c.unit, bench_name, c.name, c.bench, c.unit,
        UnitSlipHint(c.runner, c.bench), where, c.name));
  }
}

}  // namespace hybridtest::transfer
