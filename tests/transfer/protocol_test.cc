// Messages of the bench protocol: every message type round-trips through bytes, and decoders
// reject payloads of the wrong type or length.
#include "hybridtest/transfer/protocol.h"

#include <array>
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
    const Frame f = ThroughWire(EncodeCommands(42, std::array<double, 1>{position}));
    EXPECT_EQ(f.sequence, 42u);
    EXPECT_EQ(f.payload.size(), 8u);
    EXPECT_EQ(DecodeCommands(f), std::vector<double>{position});
  }
}

TEST(Protocol, MeasurementRoundTripKeepsNaN) {
  std::array<Measurement, 1> m{Measurement{12.5, -3.25e3, 1.13}};
  const Frame f = ThroughWire(EncodeMeasurements(7, m));
  EXPECT_EQ(f.payload.size(), 28u);  // the one-actuator frame: 3 f64 and the u32 status
  const Measurement back = DecodeMeasurements(f, 1).at(0);
  EXPECT_EQ(back.position, 12.5);
  EXPECT_EQ(back.force, -3.25e3);
  EXPECT_EQ(back.lab_time, 1.13);
  m[0].force = std::nan("");
  EXPECT_TRUE(std::isnan(DecodeMeasurements(ThroughWire(EncodeMeasurements(8, m)), 1)[0].force));
}

TEST(Protocol, MeasurementWithUnknownStatusIsRejected) {
  Frame f = EncodeMeasurements(3, std::array<Measurement, 1>{});
  f.payload[24] = 9;  // status field
  EXPECT_THROW(DecodeMeasurements(ThroughWire(f), 1), TransferError);
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
  const Frame command = EncodeCommands(1, std::array<double, 1>{1.0});
  EXPECT_THROW(DecodeMeasurements(command, 1), TransferError);
  EXPECT_THROW(DecodeEmpty(command, MessageType::kHeartbeat), TransferError);
  Frame longer = command;
  longer.payload.push_back(0);
  EXPECT_THROW(DecodeCommands(longer), TransferError);
  Frame shorter = command;
  shorter.payload.pop_back();
  try {
    DecodeCommands(shorter);
    FAIL() << "expected a TransferError";
  } catch (const TransferError& e) {
    EXPECT_NE(std::string(e.what()).find("a payload of 7 bytes; expected n ≥ 1 positions of 8 "
                                         "bytes"), std::string::npos);
  }
  Frame hb = EncodeEmpty(MessageType::kHeartbeat, 1);
  hb.payload.push_back(1);
  EXPECT_THROW(DecodeEmpty(hb, MessageType::kHeartbeat), TransferError);
}

}  // namespace
}  // namespace hybridtest::transfer
