#pragma once
// The `transfer: {type: modbus}` section of a physical substructure (docs/modbus.md):
//
//   transfer:
//     type: modbus
//     host: 192.168.0.10        # the controller's address (--bench HOST:PORT overrides host
//     port: 502                 #   and port)
//     unit_id: 1                # Modbus unit identifier
//     timeout: 5                # [s] longest wait for the ack of one command (default:
//                               #   the substructure's safety.timeout)
//     response_timeout: 1       # [s] longest wait for the answer to one request
//     connect_timeout: 5        # [s] longest wait for the TCP connection
//     hold_timeout: 0.5         # [s] longest wait for the answer to the hold request
//     poll_interval: 0          # [s] pause between two reads while waiting for the ack
//     plausibility: {position_tolerance: 1, force: 1e6}   # first exchange, bench units
//                               #   (default: 1 mm and 1 MN in the map's units)
//     settle_tolerance: 0.05    # the controller's settling (in-position) window, in the
//                               #   map's length unit (default 0.05 mm; at most the slot's
//                               #   max_increment). A command that moved by more than two
//                               #   windows acked with the previous position, bit for bit:
//                               #   SafetyStop "stale_acknowledgement".
//     following_error: 0.2      # every exchange: largest |command − measured position| once
//                               #   the ack is in, in the map's length unit (default: four
//                               #   settle_tolerance, at most the slot's safety.max_increment;
//                               #   refused if longer than the stroke). Beyond it: SafetyStop
//                               #   "following_error". Several actuators: one value for all,
//                               #   or a list of one per actuator
//                               #   (transfer/safety_settled_reading.h)
//     map: {...}                # register map (register_map.h); default profile if absent;
//                               #   `actuators: n` with `stride:` or `per_actuator:` for a
//                               #   controller of several actuators (register_map.h)
#include <memory>
#include <optional>
#include <string>

#include <yaml-cpp/yaml.h>

#include "hybridtest/common/yaml_input.h"
#include "hybridtest/transfer/modbus/modbus_transfer.h"
#include "hybridtest/transfer/safety.h"

namespace hybridtest::transfer::modbus {

// Reads the section at key path `kp`. `bench_address` (--bench HOST:PORT) overrides host and
// port; `default_timeout` [s] is the ack timeout unless `timeout` is given. `limits` are the
// slot's safety limits (SI; null: SafetyLimits' defaults): following_error defaults to four
// settle_tolerance, at most their max_increment, and may not exceed their stroke. Throws ConfigError.
ModbusOptions ParseModbusOptions(const YamlInput& in, const YAML::Node& node,
                                 const std::string& kp,
                                 const std::optional<std::string>& bench_address,
                                 double default_timeout, const SafetyLimits* limits = nullptr);

}  // namespace hybridtest::transfer::modbus
