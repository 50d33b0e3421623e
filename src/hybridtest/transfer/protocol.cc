#include "hybridtest/transfer/protocol.h"

#include <fmt/core.h>

#include "hybridtest/common/error.h"

namespace hybridtest::transfer {
namespace {

void ExpectType(const Frame& frame, MessageType expected) {
  if (frame.type != expected) {
    throw TransferError(fmt::format(
        "expected a {} frame, received {} (sequence {})",
        MessageTypeName(static_cast<std::uint16_t>(expected)),
        MessageTypeName(static_cast<std::uint16_t>(frame.type)), frame.sequence));
  }
}

ByteReader ReaderFor(const Frame& frame, MessageType expected) {
  ExpectType(frame, expected);
  return ByteReader(frame.payload,
                    MessageTypeName(static_cast<std::uint16_t>(expected)) + " payload");
}

Frame MakeFrame(MessageType type, std::uint32_t sequence, ByteWriter& writer) {
  Frame frame;
  frame.type = type;
  frame.sequence = sequence;
  frame.payload = writer.Take();
  return frame;
}

}  // namespace

std::string ErrorCodeName(std::uint16_t code) {
  switch (static_cast<ErrorCode>(code)) {
    case ErrorCode::kProtocol: return "PROTOCOL";
    case ErrorCode::kVersion: return "VERSION";
    case ErrorCode::kAuth: return "AUTH";
    case ErrorCode::kSafety: return "SAFETY";
    case ErrorCode::kBench: return "BENCH";
    case ErrorCode::kBusy: return "BUSY";
    case ErrorCode::kTimeout: return "TIMEOUT";
  }
  return fmt::format("UNKNOWN({})", code);
}

Frame EncodeHello(std::uint32_t sequence, const HelloMessage& message) {
  ByteWriter w;
  w.U16(message.version);
  w.Str(message.token);
  w.Str(message.client_name);
  return MakeFrame(MessageType::kHello, sequence, w);
}

HelloMessage DecodeHello(const Frame& frame) {
  ByteReader r = ReaderFor(frame, MessageType::kHello);
  HelloMessage m;
  m.version = r.U16("version");
  m.token = r.Str("token");
  m.client_name = r.Str("client_name");
  r.Finish();
  return m;
}

Frame EncodeWelcome(std::uint32_t sequence, const WelcomeMessage& message) {
  ByteWriter w;
  w.U16(message.version);
  w.Str(message.description);
  w.F64(message.units.metres_per_length_unit);
  w.F64(message.units.newtons_per_force_unit);
  w.Str(message.units.length_name);
  w.Str(message.units.force_name);
  w.F64(message.limits.stroke_min);
  w.F64(message.limits.stroke_max);
  w.F64(message.limits.max_increment);
  w.F64(message.limits.force_soft);
  w.F64(message.limits.force_hard);
  w.F64(message.heartbeat_timeout);
  if (message.actuators > 1) w.U16(static_cast<std::uint16_t>(message.actuators));
  return MakeFrame(MessageType::kWelcome, sequence, w);
}

WelcomeMessage DecodeWelcome(const Frame& frame) {
  ByteReader r = ReaderFor(frame, MessageType::kWelcome);
  WelcomeMessage m;
  m.version = r.U16("version");
  m.description = r.Str("description");
  m.units.metres_per_length_unit = r.F64("metres_per_length_unit");
  m.units.newtons_per_force_unit = r.F64("newtons_per_force_unit");
  m.units.length_name = r.Str("length_name");
  m.units.force_name = r.Str("force_name");
  m.limits.stroke_min = r.F64("stroke_min");
  m.limits.stroke_max = r.F64("stroke_max");
  m.limits.max_increment = r.F64("max_increment");
  m.limits.force_soft = r.F64("force_soft");
  m.limits.force_hard = r.F64("force_hard");
  m.heartbeat_timeout = r.F64("heartbeat_timeout");
  if (r.remaining() > 0) m.actuators = r.U16("actuators");
  r.Finish();
  return m;
}

Frame EncodeCommands(std::uint32_t sequence, std::span<const double> positions) {
  ByteWriter w;
  for (const double p : positions) w.F64(p);
  return MakeFrame(MessageType::kCommand, sequence, w);
}

std::vector<double> DecodeCommands(const Frame& frame) {
  ByteReader r = ReaderFor(frame, MessageType::kCommand);
  if (frame.payload.empty() || frame.payload.size() % 8 != 0) {
    throw TransferError(fmt::format("COMMAND (sequence {}): a payload of {} bytes; expected n ≥ 1 "
                                    "positions of 8 bytes", frame.sequence, frame.payload.size()));
  }
  std::vector<double> positions;
  while (r.remaining() > 0) positions.push_back(r.F64("position"));
  return positions;
}

Frame EncodeMeasurements(std::uint32_t sequence, std::span<const Measurement> measurements) {
  ByteWriter w;
  for (const auto& m : measurements) {
    w.F64(m.position);
    w.F64(m.force);
    w.F64(m.lab_time);
  }
  w.U32(static_cast<std::uint32_t>(MeasurementStatus::kOk));
  return MakeFrame(MessageType::kMeasurement, sequence, w);
}

std::vector<Measurement> DecodeMeasurements(const Frame& frame, int n) {
  ByteReader r = ReaderFor(frame, MessageType::kMeasurement);
  if (frame.payload.size() != static_cast<std::size_t>(n) * 24 + 4) {
    throw TransferError(fmt::format("MEASUREMENT (sequence {}): a payload of {} bytes; expected {} "
                                    "for {} actuators", frame.sequence, frame.payload.size(),
                                    n * 24 + 4, n));
  }
  std::vector<Measurement> out(static_cast<std::size_t>(n));
  for (auto& m : out) {
    m.position = r.F64("position");
    m.force = r.F64("force");
    m.lab_time = r.F64("lab_time");
  }
  const std::uint32_t status = r.U32("status");
  r.Finish();
  if (status != static_cast<std::uint32_t>(MeasurementStatus::kOk)) {
    throw TransferError(fmt::format(
        "MEASUREMENT (sequence {}): unknown status {}, expected 0 (OK)", frame.sequence, status));
  }
  return out;
}

Frame EncodeError(std::uint32_t sequence, const ErrorMessage& message) {
  ByteWriter w;
  w.U16(static_cast<std::uint16_t>(message.code));
  w.Str(message.limit);
  w.F64(message.value);
  w.F64(message.limit_value);
  w.Str(message.text);
  return MakeFrame(MessageType::kError, sequence, w);
}

ErrorMessage DecodeError(const Frame& frame) {
  ByteReader r = ReaderFor(frame, MessageType::kError);
  ErrorMessage m;
  m.code = static_cast<ErrorCode>(r.U16("code"));
  m.limit = r.Str("limit");
  m.value = r.F64("value");
  m.limit_value = r.F64("limit_value");
  m.text = r.Str("text");
  r.Finish();
  return m;
}

Frame EncodeEmpty(MessageType type, std::uint32_t sequence) {
  ByteWriter w;
  return MakeFrame(type, sequence, w);
}

void DecodeEmpty(const Frame& frame, MessageType expected) {
  ByteReader r = ReaderFor(frame, expected);
  r.Finish();
}

}  // namespace hybridtest::transfer
