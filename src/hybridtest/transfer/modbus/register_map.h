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
// The one write that carries the command and its sequence.
RegisterBlock CommandBlock(const RegisterMap& map);
// The reads that fetch position, force, ack, status and lab time: one per table used.
std::vector<RegisterBlock> ReadoutBlocks(const RegisterMap& map);

// Parses the `map:` mapping at `key_path` (undefined node: the default profile). Throws
// ConfigError naming the key path for unknown keys, bad values, overlapping fields, a command
// and sequence that one write cannot carry, or a readout wider than one request.
RegisterMap ParseRegisterMap(const YamlInput& in, const YAML::Node& node,
                             const std::string& key_path);

// Throws ConfigError (prefixed with `where`) unless the map is consistent (see above).
void ValidateRegisterMap(const RegisterMap& map, const std::string& where);

}  // namespace hybridtest::transfer::modbus
