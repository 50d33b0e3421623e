// Messages of the bench protocol: every message type round-trips through bytes, and decoders
// reject payloads of the wrong type or length.
#include "hybridtest/transfer/protocol.h"

#include <gtest/gtest.h>

#include <cmath>

#include "hybridtest/common/error.h"

namespace hybridtest::transfer {
namespace {

// Encodes, serializes, parses and decodes: the whole path a message takes on the wire.
Frame ThroughWire(const Frame& frame) { return DecodeFrame(EncodeFrame(frame)); }

TEST(Protocol, HelloRoundTrip) {
  HelloMessage m{1, "s3cret token ✓", "runner on host"};
  const Frame f = ThroughWire(EncodeHello(1, m));
  EXPECT_EQ(f.type, MessageType::kHello);
  EXPECT_EQ(f.sequence, 1u);
  const HelloMessage back = DecodeHello(f);
  EXPECT_EQ(back.version, 1);
  EXPECT_EQ(back.token, m.token);
  EXPECT_EQ(back.client_name, m.client_name);
}

TEST(Protocol, WelcomeRoundTrip) {
  WelcomeMessage m;
  m.description = "emulated bench (cantilever)";
  m.units = BenchUnits{1e-3, 1e3, "mm", "kN"};
  m.limits.stroke_min = -0.1;
  m.limits.stroke_max = 0.12;
  m.limits.max_increment = 0.004;
  m.limits.force_soft = 7e3;
  m.limits.force_hard = 9e3;
  m.heartbeat_timeout = 12.5;
  const WelcomeMessage back = DecodeWelcome(ThroughWire(EncodeWelcome(1, m)));
  EXPECT_EQ(back.description, m.description);
  EXPECT_EQ(back.units.metres_per_length_unit, 1e-3);
  EXPECT_EQ(back.units.newtons_per_force_unit, 1e3);
  EXPECT_EQ(back.units.length_name, "mm");
  EXPECT_EQ(back.units.force_name, "kN");
  EXPECT_EQ(back.limits.stroke_min, -0.1);
  EXPECT_EQ(back.limits.stroke_max, 0.12);
  EXPECT_EQ(back.limits.max_increment, 0.004);
  EXPECT_EQ(back.limits.force_soft, 7e3);
  EXPECT_EQ(back.limits.force_hard, 9e3);
  EXPECT_EQ(back.heartbeat_timeout, 12.5);
}

TEST(Protocol, CommandRoundTripIsBitExact) {
  for (double position : {0.0, -12.345678901234567, 1e-17, 149.99999999999997}) {
    const Frame f = ThroughWire(EncodeCommand(42, CommandMessage{position}));
    EXPECT_EQ(f.sequence, 42u);
    EXPECT_EQ(DecodeCommand(f).position, position);
  }
}

TEST(Protocol, MeasurementRoundTripKeepsNaN) {
  MeasurementMessage m;
  m.measurement = Measurement{12.5, -3.25e3, 1.13};
  const MeasurementMessage back = DecodeMeasurement(ThroughWire(EncodeMeasurement(7, m)));
  EXPECT_EQ(back.measurement.position, 12.5);
  EXPECT_EQ(back.measurement.force, -3.25e3);
  EXPECT_EQ(back.measurement.lab_time, 1.13);
  EXPECT_EQ(back.status, MeasurementStatus::kOk);
  m.measurement.force = std::nan("");
  EXPECT_TRUE(std::isnan(DecodeMeasurement(ThroughWire(EncodeMeasurement(8, m))).measurement.force));
}

TEST(Protocol, MeasurementWithUnknownStatusIsRejected) {
  Frame f = EncodeMeasurement(3, MeasurementMessage{});
  f.payload[24] = 9;  // status field
  EXPECT_THROW(DecodeMeasurement(ThroughWire(f)), TransferError);
}

TEST(Protocol, ErrorRoundTrip) {
  ErrorMessage m{ErrorCode::kSafety, "stroke_max", 0.2, 0.15, "command beyond the stroke"};
  const ErrorMessage back = DecodeError(ThroughWire(EncodeError(9, m)));
  EXPECT_EQ(back.code, ErrorCode::kSafety);
  EXPECT_EQ(back.limit, "stroke_max");
  EXPECT_EQ(back.value, 0.2);
  EXPECT_EQ(back.limit_value, 0.15);
  EXPECT_EQ(back.text, m.text);
  EXPECT_EQ(ErrorCodeName(4), "SAFETY");
  EXPECT_EQ(ErrorCodeName(99), "UNKNOWN(99)");
}

TEST(Protocol, EmptyMessagesRoundTrip) {
  for (MessageType t : {MessageType::kHeartbeat, MessageType::kHeartbeatAck, MessageType::kHold,
                        MessageType::kHoldAck, MessageType::kBye}) {
    const Frame f = ThroughWire(EncodeEmpty(t, 5));
    EXPECT_EQ(f.type, t);
    EXPECT_TRUE(f.payload.empty());
    EXPECT_NO_THROW(DecodeEmpty(f, t));
  }
}

TEST(Protocol, DecodersCheckTypeAndLength) {
  const Frame command = EncodeCommand(1, CommandMessage{1.0});
  EXPECT_THROW(DecodeMeasurement(command), TransferError);
  EXPECT_THROW(DecodeEmpty(command, MessageType::kHeartbeat), TransferError);
  Frame longer = command;
  longer.payload.push_back(0);
  EXPECT_THROW(DecodeCommand(longer), TransferError);
  Frame shorter = command;
  shorter.payload.pop_back();
  try {
    DecodeCommand(shorter);
    FAIL() << "expected a TransferError";
  } catch (const TransferError& e) {
    EXPECT_NE(std::string(e.what()).find("COMMAND payload too short"), std::string::npos);
  }
  Frame hb = EncodeEmpty(MessageType::kHeartbeat, 1);
  hb.payload.push_back(1);
  EXPECT_THROW(DecodeEmpty(hb, MessageType::kHeartbeat), TransferError);
}

}  // namespace
}  // namespace hybridtest::transfer
