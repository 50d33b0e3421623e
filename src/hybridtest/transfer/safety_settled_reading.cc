// See safety_settled_reading.h.
#include "hybridtest/transfer/safety_settled_reading.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/safety.h"

namespace hybridtest::transfer {

double DefaultFollowingError(double settle_tolerance, double max_increment) {
  return std::min(kFollowingErrorPerSettleTolerance * settle_tolerance, max_increment);
}

double InBenchUnit(double metres, double metres_per_unit) {
  const double value = metres / metres_per_unit;
  if (!std::isfinite(value) || value == 0.0) return value;
  return std::stod(fmt::format("{:.12g}", value));
}

SettledReadingCheck::SettledReadingCheck(std::vector<Limits> limits) : limits_(std::move(limits)) {
  for (std::size_t k = 0; k < limits_.size(); ++k) {
    const Limits& l = limits_[k];
    if (!(l.following_error > 0.0) || !std::isfinite(l.following_error)) {
      throw ConfigError(fmt::format("following_error {} (actuator {}): expected a positive "
                                    "number in the bench's length unit", l.following_error,
                                    k + 1));
    }
    if (!(l.settle_tolerance > 0.0) || !std::isfinite(l.settle_tolerance)) {
      throw ConfigError(fmt::format("settle_tolerance {} (actuator {}): expected a positive "
                                    "number in the bench's length unit", l.settle_tolerance,
                                    k + 1));
    }
  }
}

void SettledReadingCheck::Reset() {
  last_command_.clear();
  last_position_.clear();
}

void SettledReadingCheck::Check(std::span<const double> commands,
                                std::span<const double> positions, const Source& source) {
  const std::size_t n = limits_.size();
  if (commands.size() != n || positions.size() != n) {
    throw Error(fmt::format("SettledReadingCheck::Check: {} commands and {} positions for {} "
                            "actuators", commands.size(), positions.size(), n));
  }
  const std::string& unit = source.unit;
  const double metres = source.metres_per_unit;
  for (std::size_t k = 0; k < n; ++k) {
    const Limits& l = limits_[k];
    const std::string detail = source.detail ? source.detail(k) : std::string();
    // 1. A stale acknowledgement: the command moved, the reading did not.
    if (!last_command_.empty()) {
      const double moved = std::abs(commands[k] - last_command_[k]);
      const double window = 2.0 * l.settle_tolerance;
      if (moved > window && positions[k] == last_position_[k]) {
        throw SafetyStop(
            "stale_acknowledgement", moved * metres, window * metres, -1, -1, {},
            fmt::format("{} but the measured position {} {} is the one of the previous command "
                        "{} {}, bit for bit, although the command moved by {} {} (more than "
                        "twice the settling window {} {}){}. The reading is stale: the bench "
                        "reported the move done before it updated its position and force (a "
                        "controller that writes the ack before the data, a driver that returns "
                        "a cached reading); {}. To proceed: make the bench publish position and "
                        "force before it acknowledges; if its settling window is wider, set "
                        "{} ({})",
                        source.answered(k), positions[k], unit, last_command_[k], unit, moved,
                        unit, l.settle_tolerance, unit, detail, source.after, source.settle_key,
                        unit));
      }
    }
    // 2. The following error: the settled actuator must be where it was sent.
    const double following = std::abs(commands[k] - positions[k]);
    if (!(following <= l.following_error)) {
      throw SafetyStop(
          "following_error", following * metres, l.following_error * metres, -1, -1, {},
          fmt::format("{} but measured position {} {}: |command − position| = {} {} > "
                      "following_error {} {}{}. The actuator is not where it was sent (blocked "
                      "or slipping, a drive that ignores commands, a position sensor fault); "
                      "{}. To proceed: find the cause at the bench; the limit is {} ({}; "
                      "default {:g} × {}, at most the slot's safety.max_increment)",
                      source.answered(k), positions[k], unit, following, unit,
                      l.following_error, unit, detail, source.after, source.following_key, unit,
                      kFollowingErrorPerSettleTolerance, source.settle_key));
    }
  }
  last_command_.assign(commands.begin(), commands.end());
  last_position_.assign(positions.begin(), positions.end());
}

}  // namespace hybridtest::transfer
