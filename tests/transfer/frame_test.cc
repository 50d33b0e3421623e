// Frame layer of the bench protocol: byte layout, round trips, and strict rejection of every
// kind of corruption (magic, version, type, length, truncation, CRC).
#include "hybridtest/transfer/frame.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <limits>

#include "hybridtest/common/error.h"

namespace hybridtest::transfer {
namespace {

Frame SampleFrame() {
  Frame f;
  f.type = MessageType::kCommand;
  f.sequence = 0x01020304;
  f.payload = {1, 2, 3, 4, 5, 6, 7, 8};
  return f;
}

template <typename Fn>
std::string ErrorOf(Fn&& fn) {
  try {
    fn();
  } catch (const TransferError& e) {
    return e.what();
  }
  return "<no TransferError>";
}

TEST(Frame, LayoutIsLittleEndianWithCrcOverEverythingBefore) {
  const auto bytes = EncodeFrame(SampleFrame());
  ASSERT_EQ(bytes.size(), kFrameHeaderSize + 8 + kFrameTrailerSize);
  EXPECT_EQ(std::vector<std::uint8_t>(bytes.begin(), bytes.begin() + 4),
            (std::vector<std::uint8_t>{'H', 'T', 'B', 'P'}));
  EXPECT_EQ(bytes[4], 1);  // version, low byte first
  EXPECT_EQ(bytes[5], 0);
  EXPECT_EQ(bytes[6], 3);  // COMMAND
  EXPECT_EQ(bytes[7], 0);
  EXPECT_EQ(bytes[8], 0x04);  // sequence 0x01020304, little-endian
  EXPECT_EQ(bytes[11], 0x01);
  EXPECT_EQ(bytes[12], 8);  // payload length
  // The trailer is zlib's crc32 of bytes [0, 24), little-endian (an independent computation).
  const uLong crc = crc32(0L, bytes.data(), 24);
  EXPECT_EQ(bytes[24], crc & 0xFF);
  EXPECT_EQ(bytes[27], (crc >> 24) & 0xFF);
}

TEST(Frame, RoundTripsEveryMessageType) {
  for (std::uint16_t t = 1; t <= 10; ++t) {
    Frame f = SampleFrame();
    f.type = static_cast<MessageType>(t);
    f.sequence = 1000u + t;
    const Frame back = DecodeFrame(EncodeFrame(f));
    EXPECT_EQ(back.type, f.type);
    EXPECT_EQ(back.sequence, f.sequence);
    EXPECT_EQ(back.payload, f.payload);
  }
}

TEST(Frame, RoundTripsEmptyAndMaximalPayloads) {
  Frame f = SampleFrame();
  f.payload.clear();
  EXPECT_TRUE(DecodeFrame(EncodeFrame(f)).payload.empty());
  f.payload.assign(kMaxPayloadLength, 0xA5);
  EXPECT_EQ(DecodeFrame(EncodeFrame(f)).payload.size(), kMaxPayloadLength);
}

TEST(Frame, RefusesToEncodeOversizePayload) {
  Frame f = SampleFrame();
  f.payload.assign(kMaxPayloadLength + 1, 0);
  EXPECT_NE(ErrorOf([&] { EncodeFrame(f); }).find("at most 65536"), std::string::npos);
}

TEST(Frame, RejectsBadMagic) {
  auto bytes = EncodeFrame(SampleFrame());
  bytes[0] = 'X';
  EXPECT_NE(ErrorOf([&] { DecodeFrame(bytes); }).find("bad frame magic"), std::string::npos);
}

TEST(Frame, RejectsOtherVersion) {
  auto bytes = EncodeFrame(SampleFrame());
  bytes[4] = 2;
  const std::string msg = ErrorOf([&] { DecodeFrame(bytes); });
  EXPECT_NE(msg.find("protocol version"), std::string::npos) << msg;
  EXPECT_NE(msg.find("received 2"), std::string::npos) << msg;
}

TEST(Frame, RejectsUnknownType) {
  for (std::uint8_t t : {std::uint8_t{0}, std::uint8_t{18}, std::uint8_t{200}}) {
    auto bytes = EncodeFrame(SampleFrame());
    bytes[6] = t;
    const std::string msg = ErrorOf([&] { DecodeFrameHeader(bytes); });
    EXPECT_NE(msg.find("unknown message type"), std::string::npos) << msg;
  }
}

TEST(Frame, RejectsOversizeLengthInHeader) {
  auto bytes = EncodeFrame(SampleFrame());
  bytes[12] = 0x01;
  bytes[13] = 0x00;
  bytes[14] = 0x01;  // 65537
  bytes[15] = 0x00;
  const std::string msg = ErrorOf([&] { DecodeFrameHeader(bytes); });
  EXPECT_NE(msg.find("oversize payload length"), std::string::npos) << msg;
  EXPECT_NE(msg.find("65537"), std::string::npos) << msg;
}

TEST(Frame, RejectsTruncatedAndOverlongFrames) {
  auto bytes = EncodeFrame(SampleFrame());
  const std::vector<std::uint8_t> shorter(bytes.begin(), bytes.end() - 1);
  EXPECT_NE(ErrorOf([&] { DecodeFrame(shorter); }).find("truncated"), std::string::npos);
  const std::vector<std::uint8_t> header_only(bytes.begin(), bytes.begin() + 10);
  EXPECT_NE(ErrorOf([&] { DecodeFrame(header_only); }).find("truncated"), std::string::npos);
  auto longer = bytes;
  longer.push_back(0);
  EXPECT_NE(ErrorOf([&] { DecodeFrame(longer); }).find("overlong"), std::string::npos);
}

TEST(Frame, RejectsEverySingleBitFlipInPayloadOrCrc) {
  const auto clean = EncodeFrame(SampleFrame());
  for (std::size_t i = kFrameHeaderSize; i < clean.size(); ++i) {
    for (int bit = 0; bit < 8; ++bit) {
      auto bytes = clean;
      bytes[i] ^= static_cast<std::uint8_t>(1u << bit);
      EXPECT_NE(ErrorOf([&] { DecodeFrame(bytes); }).find("CRC mismatch"), std::string::npos)
          << "byte " << i << " bit " << bit;
    }
  }
}

TEST(Frame, SequenceFlipIsCaughtByCrc) {
  auto bytes = EncodeFrame(SampleFrame());
  bytes[9] ^= 0x10;
  EXPECT_NE(ErrorOf([&] { DecodeFrame(bytes); }).find("CRC mismatch"), std::string::npos);
}

TEST(ByteCodec, DoublesAreBitExactIncludingSpecialValues) {
  const double values[] = {0.0, -0.0, 1.5, -1e-300, 6.02214076e23,
                           std::numeric_limits<double>::infinity(),
                           std::numeric_limits<double>::denorm_min()};
  ByteWriter w;
  for (double v : values) w.F64(v);
  w.F64(std::numeric_limits<double>::quiet_NaN());
  const auto bytes = w.Take();
  // values[2] = 1.5 = 0x3FF8000000000000, little-endian: its last byte is 0x3F.
  EXPECT_EQ(bytes[16 + 7], 0x3F);
  EXPECT_EQ(bytes[16 + 6], 0xF8);
  ByteReader r(bytes, "test payload");
  for (double v : values) {
    const double back = r.F64("v");
    EXPECT_EQ(std::signbit(back), std::signbit(v));
    EXPECT_EQ(back, v);
  }
  EXPECT_TRUE(std::isnan(r.F64("nan")));
  r.Finish();
}

TEST(ByteCodec, ReaderIsStrictAboutLength) {
  ByteWriter w;
  w.U16(7);
  w.Str("token");
  const auto bytes = w.Take();
  ByteReader short_reader(std::span<const std::uint8_t>(bytes).first(4), "HELLO payload");
  short_reader.U16("version");
  const std::string msg = ErrorOf([&] { short_reader.Str("token"); });
  EXPECT_NE(msg.find("HELLO payload too short"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'token'"), std::string::npos) << msg;
  ByteReader long_reader(bytes, "HELLO payload");
  long_reader.U16("version");
  EXPECT_NE(ErrorOf([&] { long_reader.Finish(); }).find("too long"), std::string::npos);
}

}  // namespace
}  // namespace hybridtest::transfer
