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

}  // namespace hybridtest::transfer::modbus
