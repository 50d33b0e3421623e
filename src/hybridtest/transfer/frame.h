#pragma once
// Frames of the hybridtest bench protocol, version 1 (docs/protocol.md is the full spec).
//
// Every frame on the wire, all integers little-endian:
//
//   offset  size  field
//        0     4  magic          'H' 'T' 'B' 'P'  (0x48 0x54 0x42 0x50)
//        4     2  version        u16, kProtocolVersion = 1
//        6     2  type           u16, a MessageType
//        8     4  sequence       u32
//       12     4  payload_length u32, at most kMaxPayloadLength
//       16     n  payload        n = payload_length bytes
//     16+n     4  crc32          u32, zlib's crc32 over bytes [0, 16+n)
//
// Decoding is strict: a bad magic, version, type, length or CRC each raise a TransferError
// that names the field, the value expected and the value received.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace hybridtest::transfer {

inline constexpr std::array<std::uint8_t, 4> kFrameMagic = {0x48, 0x54, 0x42, 0x50};  // "HTBP"
inline constexpr std::uint16_t kProtocolVersion = 1;
inline constexpr std::size_t kFrameHeaderSize = 16;   // [bytes]
inline constexpr std::size_t kFrameTrailerSize = 4;   // CRC-32. [bytes]
inline constexpr std::uint32_t kMaxPayloadLength = 65536;  // [bytes]

enum class MessageType : std::uint16_t {
  kHello = 1,         // client → server: protocol version, token, client name
  kWelcome = 2,       // server → client: bench description, units, limits
  kCommand = 3,       // client → server: actuator position (bench length unit)
  kMeasurement = 4,   // server → client: position, force, lab time, status
  kHeartbeat = 5,     // client → server: keep the session alive
  kHeartbeatAck = 6,  // server → client
  kHold = 7,          // client → server: put the bench in its safe state
  kHoldAck = 8,       // server → client
  kError = 9,         // either way: code, limit, values, text
  kBye = 10,          // either way: end of session
  kRead = 11,         // client → server: every actuator's position and force, no move
  // The site protocol (site/site_protocol.h, docs/multi-site.md) on the same framing:
  kPropose = 12,      // coordinator → site: a transaction's targets, checked, not moved
  kAccept = 13,       // site → coordinator: the proposal passed the site's gate
  kRefuse = 14,       // site → coordinator: the proposal did not; limit and reason
  kExecute = 15,      // coordinator → site: move to an accepted proposal's targets
  kResult = 16,       // site → coordinator: what a transaction measured
  kQuery = 17,        // coordinator → site: a transaction's recorded result, nothing moves
};

// "HELLO", "COMMAND", ...; "UNKNOWN(n)" for a value outside MessageType.
std::string MessageTypeName(std::uint16_t type);
bool IsKnownMessageType(std::uint16_t type);

struct Frame {
  MessageType type = MessageType::kHeartbeat;
  std::uint32_t sequence = 0;
  std::vector<std::uint8_t> payload;  // at most kMaxPayloadLength bytes
};

// The validated fixed part of a frame.
struct FrameHeader {
  MessageType type = MessageType::kHeartbeat;
  std::uint32_t sequence = 0;
  std::uint32_t payload_length = 0;  // [bytes]
};

// Serializes a frame (header, payload, CRC). Throws TransferError if the payload is too long.
std::vector<std::uint8_t> EncodeFrame(const Frame& frame);

// Validates the first kFrameHeaderSize bytes of a frame: magic, version, known type, payload
// length ≤ kMaxPayloadLength. Throws TransferError naming the bad field.
FrameHeader DecodeFrameHeader(std::span<const std::uint8_t> header);

// The size of the frame whose first bytes are `bytes` (non-empty): kFrameHeaderSize until the
// header is complete, then header, payload and CRC. Throws TransferError for a bad header
// (the codec of the servers on ServerLoop that speak these frames).
std::size_t FrameSize(std::span<const std::uint8_t> bytes);

// Decodes one complete frame occupying exactly `bytes`. Checks the header, that the size
// matches the declared payload length (truncated or trailing bytes are errors), and the CRC.
Frame DecodeFrame(std::span<const std::uint8_t> bytes);

// Checks the CRC of a complete frame whose header was already validated. Throws TransferError.
void CheckFrameCrc(std::span<const std::uint8_t> bytes);

// Little-endian writer for payloads. Strings are a u16 byte count followed by UTF-8 bytes.
class ByteWriter {
 public:
  void U16(std::uint16_t value);
  void U32(std::uint32_t value);
  void F64(double value);  // IEEE-754 binary64, little-endian
  void Str(std::string_view text);  // throws TransferError above 65535 bytes
  std::vector<std::uint8_t> Take() { return std::move(bytes_); }

 private:
  std::vector<std::uint8_t> bytes_;
};

// Strict little-endian reader for payloads: reading past the end, or Finish() with bytes left
// over, throws TransferError naming `what` (e.g. "WELCOME payload").
class ByteReader {
 public:
  ByteReader(std::span<const std::uint8_t> bytes, std::string what)
      : bytes_(bytes), what_(std::move(what)) {}
  std::uint16_t U16(std::string_view field);
  std::uint32_t U32(std::string_view field);
  double F64(std::string_view field);
  std::string Str(std::string_view field);
  void Finish() const;
  std::size_t remaining() const { return bytes_.size() - offset_; }  // [bytes]

 private:
  std::span<const std::uint8_t> Take(std::size_t n, std::string_view field);
  std::span<const std::uint8_t> bytes_;
  std::size_t offset_ = 0;
  std::string what_;
};

}  // namespace hybridtest::transfer
