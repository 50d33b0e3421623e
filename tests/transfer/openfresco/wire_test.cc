// Golden bytes of OpenFresco's mode-A wire format, written by hand from the protocol facts
// (docs/openfresco.md): the 11-int header of both client variants and the first word of every
// action. The expected bytes are hex literals, never produced by our encoder.
#include "hybridtest/transfer/openfresco/wire.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "hybridtest/common/error.h"

namespace hybridtest::transfer::openfresco {
namespace {

std::vector<std::uint8_t> Hex(const std::string& hex) {
  std::vector<std::uint8_t> out;
  for (std::size_t i = 0; i + 1 < hex.size(); i += 2) {
    out.push_back(static_cast<std::uint8_t>(std::stoi(hex.substr(i, 2), nullptr, 16)));
  }
  return out;
}

// The plain-C client's header for n = 4: {4,4,4,0,0, 0,0,0,4,0, 256}, little-endian int32.
const std::string kPlainHeader4 =
    "04000000" "04000000" "04000000" "00000000" "00000000"
    "00000000" "00000000" "00000000" "04000000" "00000000"
    "00010000";
// OpenSees's header for n = 2: {2,2,2,0,1, 0,0,0,2,0, 256}.
const std::string kOpenSeesHeader2 =
    "02000000" "02000000" "02000000" "00000000" "01000000"
    "00000000" "00000000" "00000000" "02000000" "00000000"
    "00010000";

TEST(OpenFrescoWire, PlainHeaderMatchesGoldenBytes) {
  Header h;
  h.size_ctrl = {4, 4, 4, 0, 0};
  h.size_daq = {0, 0, 0, 4, 0};
  h.data_size = 256;
  EXPECT_EQ(EncodeHeader(h), Hex(kPlainHeader4));
  EXPECT_EQ(DecodeHeader(Hex(kPlainHeader4)), h);
  EXPECT_EQ(PlainHeader(4), h);
  EXPECT_NO_THROW(ValidateHeader(h));
}

TEST(OpenFrescoWire, OpenSeesHeaderWithTimeSizeOneIsAccepted) {
  const Header h = DecodeHeader(Hex(kOpenSeesHeader2));
  EXPECT_EQ(h.dofs(), 2);
  EXPECT_EQ(h.size_ctrl[kTime], 1);
  EXPECT_EQ(h.size_daq[kForce], 2);
  EXPECT_EQ(h.data_size, 256);
  EXPECT_NO_THROW(ValidateHeader(h));
}

TEST(OpenFrescoWire, LargeElementNeedsNSquaredWords) {
  // OpenSees: dataSize = max(256, 3n+2, n²) → 400 for n = 20.
  EXPECT_EQ(PlainHeader(20).data_size, 400);
  Header h = PlainHeader(20);
  EXPECT_NO_THROW(ValidateHeader(h));
  h.data_size = 256;  // too small for the 20 × 20 stiffness
  EXPECT_THROW(ValidateHeader(h), TransferError);
}

TEST(OpenFrescoWire, BadHeadersAreRejectedNamingTheField) {
  const auto message = [](const Header& h) {
    try {
      ValidateHeader(h);
    } catch (const TransferError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  Header h = PlainHeader(4);
  h.data_size = 8;  // wrong dataSize: 4 × 4 matrix needs 16
  EXPECT_NE(message(h).find("dataSize = 8 is too small"), std::string::npos) << message(h);
  h = PlainHeader(4);
  h.data_size = -1;
  EXPECT_NE(message(h).find("dataSize = -1"), std::string::npos);
  h = PlainHeader(4);
  h.size_ctrl[kDisp] = 0;
  EXPECT_NE(message(h).find("n >= 1"), std::string::npos);
  h = PlainHeader(4);
  h.size_daq[kTime] = -3;
  EXPECT_NE(message(h).find("sizeDaq time = -3"), std::string::npos);
  h = PlainHeader(4);
  h.size_ctrl[kVel] = 1 << 30;
  EXPECT_NE(message(h).find("sizeCtrl vel"), std::string::npos);
  EXPECT_THROW(DecodeHeader(Hex("0400000004000000")), TransferError);  // truncated
}

// Word 0 of a client message for every action, hand-packed IEEE 754 little-endian doubles.
struct GoldenAction {
  int action;
  const char* word0;
};
const GoldenAction kActions[] = {
    {3, "0000000000000840"},  {5, "0000000000001440"},  {6, "0000000000001840"},
    {7, "0000000000001c40"},  {8, "0000000000002040"},  {9, "0000000000002240"},
    {10, "0000000000002440"}, {11, "0000000000002640"}, {12, "0000000000002840"},
    {13, "0000000000002a40"}, {14, "0000000000002c40"}, {15, "0000000000002e40"},
    {98, "0000000000805840"}, {99, "0000000000c05840"},
};

TEST(OpenFrescoWire, EveryActionMessageMatchesGoldenBytes) {
  for (const GoldenAction& g : kActions) {
    std::vector<std::uint8_t> expected = Hex(g.word0);
    expected.resize(256 * 8, 0);  // zero-padded to dataSize words
    const std::vector<double> words{static_cast<double>(g.action)};
    EXPECT_EQ(EncodeMessage(words, 256), expected) << "action " << g.action;
    EXPECT_EQ(ActionOf(DecodeMessage(expected)), g.action);
    EXPECT_NE(ActionName(g.action), "unknown");
  }
}

TEST(OpenFrescoWire, TrialMessageMatchesGoldenBytes) {
  // [3 | d | v | a] with d = (0, 0, 1.06017, −0.355778), v = a = 0, n = 4, dataSize 16.
  std::vector<std::uint8_t> expected = Hex(
      "0000000000000840"                                                  // 3
      "0000000000000000" "0000000000000000"                               // d1, d2 = 0
      "833463d174f6f03f" "f1b8a81611c5d6bf");                             // 1.06017, −0.355778
  expected.resize(16 * 8, 0);
  const std::vector<double> words{3.0, 0.0, 0.0, 1.06017, -0.355778};
  EXPECT_EQ(EncodeMessage(words, 16), expected);
  const std::vector<double> back = DecodeMessage(expected);
  ASSERT_EQ(back.size(), 16u);
  EXPECT_EQ(back[3], 1.06017);
  EXPECT_EQ(back[4], -0.355778);
}

TEST(OpenFrescoWire, ActionWordMustBeAWholeNumber) {
  EXPECT_EQ(ActionOf(std::vector<double>{3.5}), -1);
  EXPECT_EQ(ActionOf(std::vector<double>{-1.0}), -1);
  EXPECT_EQ(ActionOf(std::vector<double>{1e300}), -1);
  EXPECT_EQ(ActionOf(std::vector<double>{std::numeric_limits<double>::quiet_NaN()}), -1);
  EXPECT_EQ(ActionOf(std::vector<double>{}), -1);
  EXPECT_EQ(ActionName(42), "unknown");
}

TEST(OpenFrescoWire, MessagesThatDoNotFitAreErrors) {
  EXPECT_THROW(EncodeMessage(std::vector<double>(17, 1.0), 16), TransferError);
  EXPECT_THROW(DecodeMessage(Hex("00000000000008")), TransferError);  // 7 bytes
}

TEST(OpenFrescoWire, TokenPreambleMatchesGoldenBytes) {
  // "HTOK", int32 length 3, "abc".
  EXPECT_EQ(EncodeTokenPreamble("abc"), Hex("48544f4b" "03000000" "616263"));
  EXPECT_THROW(EncodeTokenPreamble(""), TransferError);
  EXPECT_THROW(EncodeTokenPreamble(std::string(kMaxTokenBytes + 1, 'x')), TransferError);
  // The magic word is never a valid sizeCtrl[0].
  EXPECT_GT(kTokenMagic, kMaxDofs);
}

// The opening as the server's non-blocking handshake measures it, byte by byte.
TEST(OpenFrescoWire, OpeningSizeGrowsAsTheBytesTellMore) {
  const std::vector<std::uint8_t> header = EncodeHeader(PlainHeader(1));
  std::vector<std::uint8_t> opening = EncodeTokenPreamble("abc");
  opening.insert(opening.end(), header.begin(), header.end());
  const std::span<const std::uint8_t> with_token(opening);
  EXPECT_EQ(OpeningSize(with_token.first(0)), 4u);
  EXPECT_EQ(OpeningSize(with_token.first(4)), 8u);   // the magic word: a preamble follows
  EXPECT_EQ(OpeningSize(with_token.first(8)), 8u + 3u + kHeaderBytes);
  EXPECT_EQ(OpeningSize(with_token), opening.size());
  const Opening decoded = DecodeOpening(with_token);
  EXPECT_TRUE(decoded.has_token);
  EXPECT_EQ(decoded.token, "abc");
  EXPECT_EQ(decoded.header, PlainHeader(1));
  // Without a preamble: the 44-byte header alone.
  EXPECT_EQ(OpeningSize(std::span<const std::uint8_t>(header).first(4)), kHeaderBytes);
  const Opening plain = DecodeOpening(header);
  EXPECT_FALSE(plain.has_token);
  EXPECT_EQ(plain.header, PlainHeader(1));
  // A preamble length outside 1..kMaxTokenBytes is refused as soon as it is known.
  EXPECT_THROW(OpeningSize(Hex("48544f4b" "00000000")), TransferError);
  EXPECT_THROW(OpeningSize(Hex("48544f4b" "ffffffff")), TransferError);
  EXPECT_THROW(OpeningSize(Hex("48544f4b" "01100000")), TransferError);  // 4097
  // An incomplete or over-long opening does not decode.
  EXPECT_THROW(DecodeOpening(with_token.first(20)), TransferError);
  std::vector<std::uint8_t> longer = opening;
  longer.push_back(0);
  EXPECT_THROW(DecodeOpening(longer), TransferError);
}

}  // namespace
}  // namespace hybridtest::transfer::openfresco
