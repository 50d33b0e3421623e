#pragma once
// Several actuators on one Modbus/TCP controller: one register block per actuator
// (docs/modbus.md, "Several actuators"). Actuator k has a whole RegisterMap of its own (its
// command, sequence, position, force, ack, status with its bits, and coils); units, word and
// byte order and the lab-time register are the controller's and shared by every actuator
// (the lab time is read once, from actuator 1's map).
//
//   map:
//     ...                                # actuator 1's fields, as for one actuator
//     actuators: 2                       # n (default 1; or the length of per_actuator)
//     stride: {holding: 3, input: 6, coils: 2}   # actuator k + 1's fields lie this many
//                                        #   addresses after actuator k's. Default per table:
//                                        #   the width of actuator 1's block (packed blocks);
//                                        #   coils: 0 shares one enable and one hold coil
//     per_actuator:                      # optional, n entries: fields given here replace the
//       - {}                             #   strided ones of that actuator (a field's keys
//       - {command: {address: 100}, sequence: {address: 102}, hold_coil: 11}  # start from them)
//
// Rules (ConfigError naming the key path and the fix): every actuator's map obeys the
// one-actuator rules (register_map.h); no register of one actuator overlaps a register of
// another or the lab time; a coil is one actuator's, or the same role (enable, hold) of every
// actuator that names it.
//
// Requests: the command blocks (command + sequence) of actuators that follow each other
// without a gap go in one write (function 16, at most 123 registers); the readout registers
// of every actuator are read per table in as few requests (of at most 125 registers) as
// their addresses allow.
#include <optional>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "hybridtest/common/yaml_input.h"
#include "hybridtest/transfer/modbus/register_map.h"

namespace hybridtest::transfer::modbus {

inline constexpr int kMaxReadRegisters = 125;   // function 3 and 4
inline constexpr int kMaxWriteRegisters = 123;  // function 16

// Address offset from one actuator's fields to the next one's; unset: packed (the width of
// actuator 1's block in that table; coils: the span of its enable and hold coils).
struct Stride {
  std::optional<int> holding, input, coils;
};

// Actuator k (0-based) of n: `base` with every register field moved by k × stride of its table
// and every coil by k × stride.coils; the lab time stays with actuator 0.
RegisterMap StridedMap(const RegisterMap& base, const Stride& stride, int k);

// One write of the command blocks of `actuators` (0-based, in address order).
struct WriteBlock {
  RegisterBlock block;
  std::vector<int> actuators;
};
std::vector<WriteBlock> CommandWrites(const std::vector<RegisterMap>& maps);
// The reads that fetch every actuator's readout and the lab time: per table (input, then
// holding), consecutive fields in address order share a request while it spans at most 125.
std::vector<RegisterBlock> ReadoutBlocks(const std::vector<RegisterMap>& maps);

// Throws ConfigError (prefixed with `where`) unless the maps fit together (see above).
// maps[k] names actuator k + 1 in messages; `fix` is appended to an overlap's message.
void ValidateActuatorMaps(const std::vector<RegisterMap>& maps, const std::string& where,
                          const std::string& fix = "");

// The unique coils of a role, in actuator order (shared coils once).
std::vector<int> EnableCoils(const std::vector<RegisterMap>& maps);
std::vector<int> HoldCoils(const std::vector<RegisterMap>& maps);

// Parses the `map:` mapping at `key_path` with its multi-actuator keys (see above): one map per
// actuator (one for a map without them). Throws ConfigError naming the key path and the fix.
std::vector<RegisterMap> ParseActuatorMaps(const YamlInput& in, const YAML::Node& node,
                                           const std::string& key_path);

}  // namespace hybridtest::transfer::modbus
