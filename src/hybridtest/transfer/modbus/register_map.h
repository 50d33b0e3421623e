#pragma once
// RegisterMap: where a Modbus/TCP controller keeps the command, its sequence number, the
// measurement and its status, and how the values are encoded. Read from the `map:` mapping of
// a `transfer: {type: modbus}` section (docs/modbus.md); every key is optional and defaults to
// the default profile below.
//
// Default profile (bench units mm and N, float32 big-endian with the high word first, unit 1):
//   holding 0–1  command position       float32 [mm]   } written together in ONE request
//   holding 2    command sequence       uint16         } (function 16)
//   input   0–1  measured position      float32 [mm]
//   input   2–3  measured force         float32 [N]
//   input   4    acknowledged sequence  uint16 (= the command sequence once settled and sampled)
//   input   5    status bits            bit 0 enabled, bit 1 fault, bit 2 holding
//   coil    0    enable                 set on Activate, cleared on Deactivate
//   coil    1    hold                   set by Hold(), cleared on Activate
//   (no lab-time register: lab time is the wall time since Activate)
//
//   map:
//     units: {length: mm, force: N}       # what the controller speaks: mm|m, N|kN
//     word_order: high_first              # high_first | low_first (32/64-bit values)
//     byte_order: big                     # big | little (the two bytes inside each register)
//     command:  {table: holding, address: 0, type: float32, scale: 1}
//     sequence: {table: holding, address: 2, type: uint16}
//     position: {table: input,   address: 0, type: float32, scale: 1}
//     force:    {table: input,   address: 2, type: float32, scale: 1}
//     ack:      {table: input,   address: 4, type: uint16}
//     status:   {table: input,   address: 5, type: uint16, enabled_bit: 0, fault_bit: 1,
//                holding_bit: 2}        # a bit of -1 is not checked; `status: none` drops it
//     lab_time: {table: input, address: 6, type: uint32, scale: 0.001}   # optional, [s]
//     enable_coil: 0                      # `none`: not written
//     hold_coil: 1                        # `none`: not written
//
// A controller of n actuators has one RegisterMap per actuator (docs/modbus.md, "Several
// actuators"); n = 1 is the case above. Actuator k has a whole RegisterMap of its own (its
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
// one-actuator rules below; no register of one actuator overlaps a register of
// another or the lab time; a coil is one actuator's, or the same role (enable, hold) of every
// actuator that names it.
//
// Requests: the command blocks (command + sequence) of actuators that follow each other
// without a gap go in one write (function 16, at most 123 registers); the readout registers
// of every actuator are read per table in as few requests (of at most 125 registers) as
// their addresses allow.
//
// A value is `raw × scale` in bench units (lab_time: in seconds); types are int16, uint16,
// int32, uint32, float32 and float64; addresses are 0-based protocol addresses (the register
// "40001" of a PLC manual is holding address 0). The command and the sequence must be holding
// registers next to each other (no gap), so that one write carries both; each readout table
// (input or holding) is read in one request of at most 125 registers.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "hybridtest/common/yaml_input.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer::modbus {

enum class Table { kHolding, kInput };
enum class ValueType { kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };
enum class WordOrder { kHighFirst, kLowFirst };
enum class ByteOrder { kBig, kLittle };

// One value in the controller's register space.
struct RegisterField {
  Table table = Table::kHolding;
  int address = 0;                     // 0-based protocol address of the first register
  ValueType type = ValueType::kFloat32;
  double scale = 1.0;                  // value = raw × scale (bench unit, or [s] for lab_time)
  int width() const;                   // number of 16-bit registers (1, 2 or 4)
  int end() const { return address + width(); }  // one past the last register
};

struct StatusBits {
  int enabled = 0;   // bit set while the drive is enabled; -1: not checked
  int fault = 1;     // bit set on a controller fault (the test stops); -1: not checked
  int holding = 2;   // bit set while the actuator holds; -1: not checked
};

struct RegisterMap {
  BenchUnits units{1e-3, 1.0, "mm", "N"};
  WordOrder word_order = WordOrder::kHighFirst;
  ByteOrder byte_order = ByteOrder::kBig;
  RegisterField command{Table::kHolding, 0, ValueType::kFloat32};
  RegisterField sequence{Table::kHolding, 2, ValueType::kUint16};
  RegisterField position{Table::kInput, 0, ValueType::kFloat32};
  RegisterField force{Table::kInput, 2, ValueType::kFloat32};
  RegisterField ack{Table::kInput, 4, ValueType::kUint16};
  std::optional<RegisterField> status = RegisterField{Table::kInput, 5, ValueType::kUint16};
  StatusBits status_bits;
  std::optional<RegisterField> lab_time;  // bench clock [s] (any origin); none: wall time
  std::optional<int> enable_coil = 0;
  std::optional<int> hold_coil = 1;

  // Sequence numbers wrap modulo this (65536 for uint16, 2^32 for uint32).
  std::uint64_t sequence_modulus() const;
};

// Encodes `value` (already in bench units) into field.width() registers at `words`.
// Integer types round to the nearest count; throws TransferError if the value does not fit.
void EncodeValue(const RegisterMap& map, const RegisterField& field, double value,
                 std::uint16_t* words);
// Decodes field.width() registers at `words` into a value (raw × scale).
double DecodeValue(const RegisterMap& map, const RegisterField& field, const std::uint16_t* words);

// "holding register 0" / "input registers 2–3": for messages.
std::string DescribeField(const RegisterField& field);

// A contiguous block of registers read or written in one request.
struct RegisterBlock {
  Table table = Table::kInput;
  int start = 0;
  int count = 0;
};
// The one write that carries one actuator's command and its sequence.
RegisterBlock CommandBlock(const RegisterMap& map);

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

// Throws ConfigError (prefixed with `where`) unless every map obeys the rules of one actuator's
// map (see above: fields that do not overlap, command and sequence adjacent holding registers,
// a readout of at most 125 registers per table, distinct coils) and the maps fit together.
// maps[k] names actuator k + 1 in messages (n > 1); `fix` is appended to an overlap's message.
void ValidateRegisterMaps(const std::vector<RegisterMap>& maps, const std::string& where,
                          const std::string& fix = "");

// The unique coils of a role, in actuator order (shared coils once).
std::vector<int> EnableCoils(const std::vector<RegisterMap>& maps);
std::vector<int> HoldCoils(const std::vector<RegisterMap>& maps);

// Parses the `map:` mapping at `key_path` (undefined node: one actuator on the default
// profile), with its keys for several actuators (see above): one map per actuator. Throws
// ConfigError naming the key path and the fix for unknown keys, bad values and broken rules.
std::vector<RegisterMap> ParseRegisterMaps(const YamlInput& in, const YAML::Node& node,
                                           const std::string& key_path);

}  // namespace hybridtest::transfer::modbus
