#include "hybridtest/transfer/frame.h"

#include <fmt/core.h>
#include <zlib.h>

#include <bit>
#include <cstring>

#include "hybridtest/common/error.h"

namespace hybridtest::transfer {
namespace {

std::uint32_t LoadU16(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8);
}

std::uint32_t LoadU32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}

void StoreU32(std::vector<std::uint8_t>& out, std::uint32_t value) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(value >> (8 * i)));
}

void PutU16(std::uint8_t* p, std::uint16_t value) {
  p[0] = static_cast<std::uint8_t>(value);
  p[1] = static_cast<std::uint8_t>(value >> 8);
}

void PutU32(std::uint8_t* p, std::uint32_t value) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<std::uint8_t>(value >> (8 * i));
}

std::uint32_t Crc32(std::span<const std::uint8_t> bytes) {
  return static_cast<std::uint32_t>(
      crc32(0L, reinterpret_cast<const Bytef*>(bytes.data()), static_cast<uInt>(bytes.size())));
}

}  // namespace

bool IsKnownMessageType(std::uint16_t type) {
  return type >= static_cast<std::uint16_t>(MessageType::kHello) &&
         type <= static_cast<std::uint16_t>(MessageType::kQuery);
}

std::string MessageTypeName(std::uint16_t type) {
  static const char* const kNames[] = {"HELLO",         "WELCOME", "COMMAND",  "MEASUREMENT",
                                       "HEARTBEAT",     "HEARTBEAT_ACK", "HOLD", "HOLD_ACK",
                                       "ERROR",         "BYE",     "READ",    "PROPOSE",
                                       "ACCEPT",        "REFUSE",  "EXECUTE", "RESULT",
                                       "QUERY"};
  if (!IsKnownMessageType(type)) return fmt::format("UNKNOWN({})", type);
  return kNames[type - 1];
}

std::size_t FrameSize(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < kFrameHeaderSize) return kFrameHeaderSize;
  const FrameHeader header = DecodeFrameHeader(bytes.first(kFrameHeaderSize));
  return kFrameHeaderSize + header.payload_length + kFrameTrailerSize;
}

std::vector<std::uint8_t> EncodeFrame(const Frame& frame) {
  if (frame.payload.size() > kMaxPayloadLength) {
    throw TransferError(fmt::format(
        "cannot encode a {} frame with a {}-byte payload: the protocol allows at most {} bytes",
        MessageTypeName(static_cast<std::uint16_t>(frame.type)), frame.payload.size(),
        kMaxPayloadLength));
  }
  // Written in place into a buffer of the final size (header, payload, CRC).
  const std::size_t body = kFrameHeaderSize + frame.payload.size();
  std::vector<std::uint8_t> out(body + kFrameTrailerSize);
  std::uint8_t* p = out.data();
  std::memcpy(p, kFrameMagic.data(), kFrameMagic.size());
  PutU16(p + 4, kProtocolVersion);
  PutU16(p + 6, static_cast<std::uint16_t>(frame.type));
  PutU32(p + 8, frame.sequence);
  PutU32(p + 12, static_cast<std::uint32_t>(frame.payload.size()));
  if (!frame.payload.empty()) {
    std::memcpy(p + kFrameHeaderSize, frame.payload.data(), frame.payload.size());
  }
  PutU32(p + body, Crc32(std::span<const std::uint8_t>(p, body)));
  return out;
}

FrameHeader DecodeFrameHeader(std::span<const std::uint8_t> header) {
  if (header.size() < kFrameHeaderSize) {
    throw TransferError(fmt::format("truncated frame: expected a {}-byte header, received {} bytes",
                                    kFrameHeaderSize, header.size()));
  }
  const std::uint8_t* p = header.data();
  if (std::memcmp(p, kFrameMagic.data(), kFrameMagic.size()) != 0) {
    throw TransferError(fmt::format(
        "bad frame magic: expected 48 54 42 50 (\"HTBP\"), received {:02x} {:02x} {:02x} {:02x}; "
        "is the peer a hybridtest bench speaking protocol v{}?",
        p[0], p[1], p[2], p[3], kProtocolVersion));
  }
  const std::uint32_t version = LoadU16(p + 4);
  if (version != kProtocolVersion) {
    throw TransferError(fmt::format(
        "unsupported protocol version in frame header: expected {}, received {}",
        kProtocolVersion, version));
  }
  const auto type = static_cast<std::uint16_t>(LoadU16(p + 6));
  if (!IsKnownMessageType(type)) {
    throw TransferError(fmt::format(
        "unknown message type in frame header: expected 1..11 (HELLO..READ), received {}", type));
  }
  FrameHeader result;
  result.type = static_cast<MessageType>(type);
  result.sequence = LoadU32(p + 8);
  result.payload_length = LoadU32(p + 12);
  if (result.payload_length > kMaxPayloadLength) {
    throw TransferError(fmt::format(
        "oversize payload length in {} frame header: at most {} bytes allowed, received {}",
        MessageTypeName(type), kMaxPayloadLength, result.payload_length));
  }
  return result;
}

void CheckFrameCrc(std::span<const std::uint8_t> bytes) {
  const std::size_t body = bytes.size() - kFrameTrailerSize;
  const std::uint32_t received = LoadU32(bytes.data() + body);
  const std::uint32_t computed = Crc32(bytes.first(body));
  if (received != computed) {
    throw TransferError(fmt::format(
        "CRC mismatch in {} frame (sequence {}): computed {:08x} over {} bytes, received {:08x}; "
        "the frame was corrupted in transit",
        MessageTypeName(static_cast<std::uint16_t>(LoadU16(bytes.data() + 6))),
        LoadU32(bytes.data() + 8), computed, body, received));
  }
}

Frame DecodeFrame(std::span<const std::uint8_t> bytes) {
  const FrameHeader header = DecodeFrameHeader(bytes);
  const std::size_t expected = kFrameHeaderSize + header.payload_length + kFrameTrailerSize;
  if (bytes.size() != expected) {
    throw TransferError(fmt::format(
        "{} frame: expected {} bytes (header, {}-byte payload, CRC), received {}",
        bytes.size() < expected ? "truncated" : "overlong",
        expected, header.payload_length, bytes.size()));
  }
  CheckFrameCrc(bytes);
  Frame frame;
  frame.type = header.type;
  frame.sequence = header.sequence;
  frame.payload.assign(bytes.begin() + kFrameHeaderSize,
                       bytes.begin() + static_cast<std::ptrdiff_t>(kFrameHeaderSize +
                                                                   header.payload_length));
  return frame;
}

void ByteWriter::U16(std::uint16_t value) {
  bytes_.push_back(static_cast<std::uint8_t>(value));
  bytes_.push_back(static_cast<std::uint8_t>(value >> 8));
}

void ByteWriter::U32(std::uint32_t value) { StoreU32(bytes_, value); }

void ByteWriter::F64(double value) {
  const auto bits = std::bit_cast<std::uint64_t>(value);
  for (int i = 0; i < 8; ++i) bytes_.push_back(static_cast<std::uint8_t>(bits >> (8 * i)));
}

void ByteWriter::Str(std::string_view text) {
  if (text.size() > 0xFFFF) {
    throw TransferError(fmt::format(
        "cannot encode a {}-byte string: protocol strings hold at most 65535 bytes", text.size()));
  }
  U16(static_cast<std::uint16_t>(text.size()));
  bytes_.insert(bytes_.end(), text.begin(), text.end());
}

std::span<const std::uint8_t> ByteReader::Take(std::size_t n, std::string_view field) {
  if (bytes_.size() - offset_ < n) {
    throw TransferError(fmt::format(
        "{} too short: field '{}' needs {} bytes at offset {}, only {} left", what_, field, n,
        offset_, bytes_.size() - offset_));
  }
  auto out = bytes_.subspan(offset_, n);
  offset_ += n;
  return out;
}

std::uint16_t ByteReader::U16(std::string_view field) {
  return static_cast<std::uint16_t>(LoadU16(Take(2, field).data()));
}

std::uint32_t ByteReader::U32(std::string_view field) { return LoadU32(Take(4, field).data()); }

double ByteReader::F64(std::string_view field) {
  const auto b = Take(8, field);
  std::uint64_t bits = 0;
  for (int i = 0; i < 8; ++i) bits |= static_cast<std::uint64_t>(b[i]) << (8 * i);
  return std::bit_cast<double>(bits);
}

std::string ByteReader::Str(std::string_view field) {
  const std::uint16_t n = U16(field);
  const auto b = Take(n, field);
  return std::string(b.begin(), b.end());
}

void ByteReader::Finish() const {
  if (offset_ != bytes_.size()) {
    throw TransferError(fmt::format("{} too long: expected {} bytes, received {}", what_, offset_,
                                    bytes_.size()));
  }
}

}  // namespace hybridtest::transfer
