// See register_map.h. Encoding, decoding and the consistency rules of a register map; the YAML
// parser is in register_map_parse.cc.
#include "hybridtest/transfer/modbus/register_map.h"

#include <fmt/core.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <utility>

#include "hybridtest/common/error.h"

namespace hybridtest::transfer::modbus {
namespace {

// The raw value's bits, most significant first, as `width` registers with the high word first
// and the bytes of each register big-endian (the Modbus convention).
std::uint64_t RawBits(const RegisterField& field, double value) {
  const double raw = value / field.scale;
  const auto integer = [&](double lo, double hi) -> std::int64_t {
    const double r = std::round(raw);
    if (!std::isfinite(raw) || r < lo || r > hi) {
      throw TransferError(fmt::format("value {} (raw {} with scale {}) does not fit the {} at {}",
                                      value, raw, field.scale,
                                      field.width() == 1 ? "16-bit register" : "32-bit registers",
                                      DescribeField(field)));
    }
    return static_cast<std::int64_t>(r);
  };
  switch (field.type) {
    case ValueType::kInt16:
      return static_cast<std::uint16_t>(static_cast<std::int16_t>(integer(-32768, 32767)));
    case ValueType::kUint16:
      return static_cast<std::uint16_t>(integer(0, 65535));
    case ValueType::kInt32:
      return static_cast<std::uint32_t>(
          static_cast<std::int32_t>(integer(-2147483648.0, 2147483647.0)));
    case ValueType::kUint32:
      return static_cast<std::uint32_t>(integer(0, 4294967295.0));
    case ValueType::kFloat32:
      return std::bit_cast<std::uint32_t>(static_cast<float>(raw));
    case ValueType::kFloat64:
      return std::bit_cast<std::uint64_t>(raw);
  }
  return 0;
}

double FromBits(const RegisterField& field, std::uint64_t bits) {
  switch (field.type) {
    case ValueType::kInt16:
      return static_cast<std::int16_t>(static_cast<std::uint16_t>(bits));
    case ValueType::kUint16:
      return static_cast<std::uint16_t>(bits);
    case ValueType::kInt32:
      return static_cast<std::int32_t>(static_cast<std::uint32_t>(bits));
    case ValueType::kUint32:
      return static_cast<std::uint32_t>(bits);
    case ValueType::kFloat32:
      return std::bit_cast<float>(static_cast<std::uint32_t>(bits));
    case ValueType::kFloat64:
      return std::bit_cast<double>(bits);
  }
  return 0.0;
}

std::uint16_t SwapBytes(std::uint16_t w) { return static_cast<std::uint16_t>((w >> 8) | (w << 8)); }

// Position of the k-th most significant word on the wire, after the word order.
int WordSlot(const RegisterMap& map, int width, int k) {
  return map.word_order == WordOrder::kHighFirst ? k : width - 1 - k;
}

const char* TableName(Table t) { return t == Table::kHolding ? "holding" : "input"; }

}  // namespace

int RegisterField::width() const {
  switch (type) {
    case ValueType::kInt16:
    case ValueType::kUint16:
      return 1;
    case ValueType::kInt32:
    case ValueType::kUint32:
    case ValueType::kFloat32:
      return 2;
    case ValueType::kFloat64:
      return 4;
  }
  return 1;
}

std::uint64_t RegisterMap::sequence_modulus() const {
  return sequence.width() == 1 ? (1ull << 16) : (1ull << 32);
}

void EncodeValue(const RegisterMap& map, const RegisterField& field, double value,
                 std::uint16_t* words) {
  const std::uint64_t bits = RawBits(field, value);
  const int width = field.width();
  for (int k = 0; k < width; ++k) {
    auto w = static_cast<std::uint16_t>(bits >> (16 * (width - 1 - k)));
    if (map.byte_order == ByteOrder::kLittle) w = SwapBytes(w);
    words[WordSlot(map, width, k)] = w;
  }
}

double DecodeValue(const RegisterMap& map, const RegisterField& field,
                   const std::uint16_t* words) {
  const int width = field.width();
  std::uint64_t bits = 0;
  for (int k = 0; k < width; ++k) {
    std::uint16_t w = words[WordSlot(map, width, k)];
    if (map.byte_order == ByteOrder::kLittle) w = SwapBytes(w);
    bits = (bits << 16) | w;
  }
  return FromBits(field, bits) * field.scale;
}

std::string DescribeField(const RegisterField& field) {
  if (field.width() == 1) return fmt::format("{} register {}", TableName(field.table), field.address);
  return fmt::format("{} registers {}–{}", TableName(field.table), field.address, field.end() - 1);
}

RegisterBlock CommandBlock(const RegisterMap& map) {
  const int start = std::min(map.command.address, map.sequence.address);
  const int end = std::max(map.command.end(), map.sequence.end());
  return {Table::kHolding, start, end - start};
}

std::vector<RegisterBlock> ReadoutBlocks(const RegisterMap& map) {
  std::vector<RegisterBlock> blocks;
  for (Table table : {Table::kInput, Table::kHolding}) {
    int start = std::numeric_limits<int>::max(), end = -1;
    for (const RegisterField* f : {&map.position, &map.force, &map.ack}) {
      if (f->table != table) continue;
      start = std::min(start, f->address);
      end = std::max(end, f->end());
    }
    for (const auto* f : {&map.status, &map.lab_time}) {
      if (!f->has_value() || (*f)->table != table) continue;
      start = std::min(start, (*f)->address);
      end = std::max(end, (*f)->end());
    }
    if (end >= 0) blocks.push_back({table, start, end - start});
  }
  return blocks;
}

void ValidateRegisterMap(const RegisterMap& map, const std::string& where) {
  const auto fail = [&](const std::string& what) {
    throw ConfigError(fmt::format("{}: {}", where, what));
  };
  std::vector<std::pair<std::string, const RegisterField*>> fields = {
      {"command", &map.command}, {"sequence", &map.sequence}, {"position", &map.position},
      {"force", &map.force},     {"ack", &map.ack}};
  if (map.status) fields.emplace_back("status", &*map.status);
  if (map.lab_time) fields.emplace_back("lab_time", &*map.lab_time);
  for (const auto& [name, f] : fields) {
    if (f->address < 0 || f->end() > 65536) {
      fail(fmt::format("{}.address = {}: expected an address in 0..{}", name, f->address,
                       65536 - f->width()));
    }
    if (!(std::abs(f->scale) > 0.0) || !std::isfinite(f->scale)) {
      fail(fmt::format("{}.scale = {}: expected a non-zero finite factor", name, f->scale));
    }
  }
  // The sequence, the ack and the status are counts and bits, not scaled floats.
  for (const auto& [name, f] : {std::pair{"sequence", &map.sequence}, std::pair{"ack", &map.ack}}) {
    if ((f->type != ValueType::kUint16 && f->type != ValueType::kUint32) || f->scale != 1.0) {
      fail(fmt::format("{}: expected type uint16 or uint32 with scale 1 (a sequence number)", name));
    }
  }
  if (map.ack.type != map.sequence.type) {
    fail("ack and sequence: expected the same type (both uint16 or both uint32)");
  }
  if (map.status && (map.status->type != ValueType::kUint16 || map.status->scale != 1.0)) {
    fail("status: expected type uint16 with scale 1 (a register of bits)");
  }
  for (int bit : {map.status_bits.enabled, map.status_bits.fault, map.status_bits.holding}) {
    if (bit < -1 || bit > 15) fail(fmt::format("status bit {}: expected 0..15, or -1 (unused)", bit));
  }
  // Fields of one table must not overlap.
  for (std::size_t i = 0; i < fields.size(); ++i) {
    for (std::size_t j = i + 1; j < fields.size(); ++j) {
      const RegisterField& a = *fields[i].second;
      const RegisterField& b = *fields[j].second;
      if (a.table == b.table && a.address < b.end() && b.address < a.end()) {
        fail(fmt::format("{} ({}) and {} ({}) overlap; give each its own registers",
                         fields[i].first, DescribeField(a), fields[j].first, DescribeField(b)));
      }
    }
  }
  // One write (function 16) carries the command and its sequence: adjacent holding registers.
  if (map.command.table != Table::kHolding || map.sequence.table != Table::kHolding) {
    fail("command and sequence: expected holding registers (they are written)");
  }
  const RegisterBlock write = CommandBlock(map);
  if (write.count != map.command.width() + map.sequence.width()) {
    fail(fmt::format("command ({}) and sequence ({}) must be adjacent so that one request "
                     "(function 16) writes both; move the sequence next to the command",
                     DescribeField(map.command), DescribeField(map.sequence)));
  }
  for (const RegisterBlock& b : ReadoutBlocks(map)) {
    if (b.count > 125) {
      fail(fmt::format("the {} registers read back span {} registers ({}..{}); one request "
                       "reads at most 125: place position, force, ack, status and lab_time "
                       "closer together", TableName(b.table), b.count, b.start,
                       b.start + b.count - 1));
    }
  }
  if (map.enable_coil && map.hold_coil && *map.enable_coil == *map.hold_coil) {
    fail(fmt::format("enable_coil and hold_coil are both coil {}: expected two coils",
                     *map.enable_coil));
  }
  for (const auto& coil : {map.enable_coil, map.hold_coil}) {
    if (coil && (*coil < 0 || *coil > 65535)) {
      fail(fmt::format("coil {}: expected an address in 0..65535", *coil));
    }
  }
}

}  // namespace hybridtest::transfer::modbus
