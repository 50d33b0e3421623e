#pragma once
// What every controller that acknowledges a settled move shares, whatever its protocol (Modbus
// registers, ADS symbols): the bounds of its waits, the plausibility of the first exchange, its
// in-position window and the following error (safety_settled_reading.h). One struct, one
// reader of the run file's keys and one resolution of the defaults, so that a new such
// protocol reads and checks them as the others do.
//
//   transfer:
//     timeout: 5                # [s] longest wait for the ack of one command (default: the
//                               #   substructure's safety.timeout)
//     response_timeout: 1       # [s] longest wait for the answer to one request
//     connect_timeout: 5        # [s] longest wait for the TCP connection
//     hold_timeout: 0.5         # [s] longest wait for the answer to the hold request
//     poll_interval: 0          # [s] pause between two reads while waiting for the ack
//     plausibility: {position_tolerance: 1, force: 1e6}   # first exchange, bench units
//     settle_tolerance: 0.05    # the controller's in-position window, bench length unit
//     following_error: 0.2      # one value, or one per actuator, bench length unit
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "hybridtest/common/yaml_input.h"
#include "hybridtest/transfer/safety.h"
#include "hybridtest/transfer/safety_settled_reading.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer {

struct ControllerOptions {
  double connect_timeout = 5.0;   // longest wait for the TCP connection. Unit: [s].
  double response_timeout = 1.0;  // longest wait for the answer to one request. Unit: [s].
  double ack_timeout = 5.0;       // longest wait for the ack of one command. Unit: [s].
  double hold_timeout = 0.5;      // longest wait for the answer to Hold()'s write. Unit: [s].
  double poll_interval = 0.0;     // pause between two reads while waiting. Unit: [s].
  // First exchange: the largest |position − command| and |force|. Unit: bench length and
  // force units. Unset: 1 mm and 1 MN in the bench's units.
  std::optional<double> position_tolerance;
  std::optional<double> force_plausible;
  // The controller's settling (in-position) window: |command − position| below which it
  // reports a move settled. Unit: bench length unit. Unset: kDefaultSettleTolerance (0.05 mm).
  std::optional<double> settle_tolerance;
  // Every exchange: the largest |command − measured position| once the ack is in. Unit: bench
  // length unit. Unset: DefaultFollowingError(settle_tolerance, SafetyLimits' max_increment)
  // (0.2 mm); ReadControllerOptions caps it at the slot's safety.max_increment instead.
  std::optional<double> following_error;
  // Several actuators: one following error each (bench length unit); empty: following_error
  // for every actuator.
  std::vector<double> following_errors;
};

// Reads the keys above of the transfer section `node` at key path `kp` into `o` (the caller
// has checked the section's keys). `default_timeout` [s] is the ack timeout unless `timeout`
// is given. `limits` are the slot's safety limits (SI; null: SafetyLimits' defaults):
// settle_tolerance may not exceed their max_increment, following_error defaults to four
// settle_tolerance, at most their max_increment, and may not exceed their stroke. `units` are
// the controller's, `actuators` the number a list of following errors must have. Throws
// ConfigError naming the key, the value and the fix.
void ReadControllerOptions(const YamlInput& in, const YAML::Node& node, const std::string& kp,
                           double default_timeout, const SafetyLimits* limits,
                           const BenchUnits& units, std::size_t actuators, ControllerOptions& o);

// Fills what `o` leaves unset (the defaults above, in `units`) and checks every value: times
// positive, poll_interval non-negative, tolerances positive and finite, one following error per
// actuator or none. Returns the settled-reading limits of each of the `actuators`. `who`
// begins the messages ("modbus transfer"). Throws ConfigError.
std::vector<SettledReadingCheck::Limits> ResolveControllerOptions(ControllerOptions& o,
                                                                  const BenchUnits& units,
                                                                  std::size_t actuators,
                                                                  std::string_view who);

}  // namespace hybridtest::transfer
