// The ADS codec (transfer/ads/ads_codec.h) against byte layouts written out by hand from the
// protocol's description: the AMS/TCP prefix, the 32-byte AMS header, the payloads, the sum
// commands and the symbol entry whose field offsets the npm client ads-client reads.
#include "hybridtest/transfer/ads/ads_codec.h"

#include <gtest/gtest.h>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/ads/ads_profile.h"

namespace hybridtest::transfer::ads {
namespace {

using Bytes = std::vector<std::uint8_t>;

TEST(AdsCodec, AmsNetIdParsesSixNumbersAndRefusesAnythingElse) {
  const auto id = ParseAmsNetId("5.80.201.232.1.1");
  ASSERT_TRUE(id.has_value());
  EXPECT_EQ(id->bytes, (std::array<std::uint8_t, 6>{5, 80, 201, 232, 1, 1}));
  EXPECT_EQ(FormatAmsNetId(*id), "5.80.201.232.1.1");
  for (const char* bad : {"", "1.2.3.4.5", "1.2.3.4.5.6.7", "1.2.3.4.5.256", "1.2.3.4.5.x",
                          "1..3.4.5.6", "1.2.3.4.5.6.", " 1.2.3.4.5.6", "1234.2.3.4.5.6"}) {
    EXPECT_FALSE(ParseAmsNetId(bad).has_value()) << bad;
  }
}

TEST(AdsCodec, AReadRequestIsTheHandWrittenPacket) {
  AmsPacket p;
  p.header.target = {{{192, 168, 0, 20, 1, 1}}, 851};
  p.header.source = {{{192, 168, 0, 5, 1, 1}}, 32905};
  p.header.command = Command::kRead;
  p.header.invoke_id = 0x01020304;
  p.data = ReadRequest(0xF005, 0x1000, 8);
  const Bytes expected = {
      0x00, 0x00, 0x2C, 0x00, 0x00, 0x00,              // AMS/TCP: reserved, length 44
      192, 168, 0, 20, 1, 1, 0x53, 0x03,               // target NetId, port 851
      192, 168, 0, 5, 1, 1, 0x89, 0x80,                // source NetId, port 32905
      0x02, 0x00, 0x04, 0x00,                          // command 2 (Read), flags 0x0004
      0x0C, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // data length 12, error 0
      0x04, 0x03, 0x02, 0x01,                          // invoke id
      0x05, 0xF0, 0x00, 0x00, 0x00, 0x10, 0x00, 0x00, 0x08, 0x00, 0x00, 0x00};
  const Bytes encoded = EncodePacket(p);
  EXPECT_EQ(encoded, expected);
  // And back.
  const Prefix prefix = DecodePrefix(std::span(encoded).first(6));
  EXPECT_EQ(prefix.reserved, 0);
  EXPECT_EQ(prefix.length, 44u);
  const AmsPacket back = DecodePacket(std::span(encoded).subspan(6));
  EXPECT_EQ(back.header.target, p.header.target);
  EXPECT_EQ(back.header.source, p.header.source);
  EXPECT_EQ(back.header.invoke_id, p.header.invoke_id);
  const IndexRequest r = DecodeReadRequest(back.data);
  EXPECT_EQ(r.group, 0xF005u);
  EXPECT_EQ(r.offset, 0x1000u);
  EXPECT_EQ(r.read_length, 8u);
}

TEST(AdsCodec, GarbledPacketsAreTransferErrors) {
  const Bytes huge = {0, 0, 0xFF, 0xFF, 0xFF, 0x7F};
  EXPECT_THROW(DecodePrefix(huge), TransferError);
  Bytes packet = EncodePacket(AmsPacket{{}, {1, 2, 3}});
  packet.pop_back();  // the header says 3 data bytes
  EXPECT_THROW(DecodePacket(std::span(packet).subspan(6)), TransferError);
  EXPECT_THROW(DecodePacket(Bytes(31, 0)), TransferError);
  EXPECT_THROW(DecodeWriteRequest(Bytes{0, 0, 0, 0, 0, 0, 0, 0, 9, 0, 0, 0, 1}), TransferError);
  EXPECT_THROW(DecodeSumWrite(2, Bytes(12, 0)), TransferError);
}

TEST(AdsCodec, ReadWriteAndItsAnswerRoundTrip) {
  const Bytes name = NameData("GVL_Hybrid.fForce");
  EXPECT_EQ(name.back(), 0);
  const Bytes request = ReadWriteRequest(kGroupHandleByName, 0, 4, name);
  ASSERT_EQ(request.size(), 16 + name.size());
  EXPECT_EQ(GetU32(request, 12), name.size());  // write length
  const IndexRequest r = DecodeReadWriteRequest(request);
  EXPECT_EQ(DataName(r.data), "GVL_Hybrid.fForce");
  EXPECT_EQ(r.read_length, 4u);
  const DataResponse answer = DecodeDataResponse(EncodeDataResponse(0, Bytes{7, 0, 0, 0}));
  EXPECT_EQ(answer.result, 0u);
  EXPECT_EQ(answer.data, (Bytes{7, 0, 0, 0}));
  // An error answer may stop after its result.
  EXPECT_EQ(DecodeDataResponse(EncodeResultResponse(0x710)).result, 0x710u);
}

TEST(AdsCodec, SumReadRequestListsHeadersAndAsksForResultsAndData) {
  const std::vector<SubRequest> items = {{kGroupValueByHandle, 0x11, 16, {}},
                                         {kGroupValueByHandle, 0x12, 4, {}}};
  const Bytes payload = SumReadRequest(items);
  const IndexRequest r = DecodeReadWriteRequest(payload);
  EXPECT_EQ(r.group, 0xF080u);
  EXPECT_EQ(r.offset, 2u);                  // number of sub-requests
  EXPECT_EQ(r.read_length, 4 + 16 + 4 + 4u);  // a result and the data of each
  ASSERT_EQ(r.data.size(), 24u);
  EXPECT_EQ(GetU32(r.data, 12), 0xF005u);
  EXPECT_EQ(GetU32(r.data, 16), 0x12u);
  EXPECT_EQ(GetU32(r.data, 20), 4u);
  const std::vector<SubRequest> back = DecodeSumRead(r.offset, r.data);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0].length, 16u);
  // The answer: results first, then each sub-request's data in order.
  const std::vector<DataResponse> answers = {{0, Bytes(16, 0xAB)}, {0x710, {}}};
  const Bytes encoded = EncodeSumReadAnswer(answers, items);
  ASSERT_EQ(encoded.size(), 8u + 16 + 4);
  EXPECT_EQ(GetU32(encoded, 4), 0x710u);
  const std::uint32_t lengths[] = {16, 4};
  const auto decoded = DecodeSumReadAnswer(encoded, lengths);
  EXPECT_EQ(decoded[0].data, Bytes(16, 0xAB));
  EXPECT_EQ(decoded[1].result, 0x710u);
  EXPECT_THROW(DecodeSumReadAnswer(std::span(encoded).first(20), lengths), TransferError);
}

TEST(AdsCodec, SumWriteCarriesHeadersThenData) {
  const std::vector<SubRequest> items = {{kGroupValueByHandle, 1, 2, {9, 8}},
                                         {kGroupValueByHandle, 2, 1, {7}}};
  const IndexRequest r = DecodeReadWriteRequest(SumWriteRequest(items));
  EXPECT_EQ(r.group, 0xF081u);
  EXPECT_EQ(r.read_length, 8u);  // one result each
  EXPECT_EQ(r.data, (Bytes{0x05, 0xF0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0,
                           0x05, 0xF0, 0, 0, 2, 0, 0, 0, 1, 0, 0, 0, 9, 8, 7}));
  const auto back = DecodeSumWrite(2, r.data);
  EXPECT_EQ(back[1].data, (Bytes{7}));
  const std::uint32_t results[] = {0, 0x705};
  EXPECT_EQ(DecodeSumWriteAnswer(EncodeSumWriteAnswer(results), 2),
            (std::vector<std::uint32_t>{0, 0x705}));
}

TEST(AdsCodec, SymbolEntryHasTheFieldOffsetsAClientReads) {
  SymbolInfo s;
  s.group = kGroupPlcData;
  s.offset = 16;
  s.size = 16;
  s.data_type = kTypeReal64;
  s.name = "GVL_Hybrid.fPosition";
  s.type = "ARRAY [1..2] OF LREAL";
  s.comment = "[mm]";
  s.array = {{1, 2}};
  const Bytes e = EncodeSymbolInfo(s);
  // entry length, group, offset, size, type id, flags u16, dimensions u16, three lengths u16
  EXPECT_EQ(GetU32(e, 0), e.size());
  EXPECT_EQ(GetU32(e, 4), 0x4040u);
  EXPECT_EQ(GetU32(e, 12), 16u);
  EXPECT_EQ(GetU32(e, 16), 5u);
  EXPECT_EQ(GetU16(e, 22), 1u);
  EXPECT_EQ(GetU16(e, 24), 20u);
  EXPECT_EQ(GetU16(e, 26), 21u);
  EXPECT_EQ(std::string(e.begin() + 30, e.begin() + 50), "GVL_Hybrid.fPosition");
  EXPECT_EQ(e[50], 0);
  EXPECT_EQ(GetU32(e, e.size() - 8), 1u);  // array start index
  EXPECT_EQ(GetU32(e, e.size() - 4), 2u);  // array length
  const SymbolInfo back = DecodeSymbolInfo(e);
  EXPECT_EQ(back.name, s.name);
  EXPECT_EQ(back.type, s.type);
  EXPECT_EQ(back.comment, s.comment);
  EXPECT_EQ(back.array, s.array);
  EXPECT_THROW(DecodeSymbolInfo(std::span(e).first(40)), TransferError);
}

TEST(AdsCodec, HandleAnswerIsTheHandleAloneOrWithSizeAndType) {
  const HandleAnswer a{0x2A, 8, "LREAL"};
  const Bytes short_answer = EncodeHandleAnswer(a, 4);
  EXPECT_EQ(short_answer, (Bytes{0x2A, 0, 0, 0}));
  EXPECT_FALSE(DecodeHandleAnswer(short_answer).size.has_value());
  const Bytes long_answer = EncodeHandleAnswer(a, 0xFFFFFFFF);
  const HandleAnswer back = DecodeHandleAnswer(long_answer);
  EXPECT_EQ(back.handle, 0x2Au);
  EXPECT_EQ(back.size, 8u);
  EXPECT_EQ(back.type, "LREAL");
}

TEST(AdsCodec, StateAndDeviceInfoRoundTrip) {
  const StateResponse s = DecodeStateResponse(EncodeStateResponse({0, kStateStop, 1}));
  EXPECT_EQ(s.ads_state, 6);
  EXPECT_EQ(AdsStateName(s.ads_state), "STOP");
  const DeviceInfo d = DecodeDeviceInfo(EncodeDeviceInfo({0, 3, 1, 4024, "Plc30 App"}));
  EXPECT_EQ(d.build, 4024);
  EXPECT_EQ(d.name, "Plc30 App");
}

TEST(AdsCodec, ErrorCodesAreNamed) {
  EXPECT_EQ(AdsErrorName(0x710), "0x710 (symbol not found)");
  EXPECT_NE(AdsErrorName(0x705).find("size"), std::string::npos);
  EXPECT_NE(AdsErrorName(0x7).find("route"), std::string::npos);
  EXPECT_EQ(AdsErrorName(0x7FF), "0x7FF (client error)");
  EXPECT_EQ(AdsErrorName(0x72F), "0x72F (device error)");
}

TEST(AdsProfile, TypesAndValuesOfNActuators) {
  EXPECT_EQ(Expected(kCommand, 3).type, "ARRAY [1..3] OF LREAL");
  EXPECT_EQ(Expected(kCommand, 3).size, 24u);
  EXPECT_EQ(Expected(kAck, 3).type, "UDINT");
  EXPECT_EQ(Expected(kFault, 1).size, 1u);
  EXPECT_EQ(DefaultProfile(2).symbols[kSequence], "GVL_Hybrid.nCommandSeq");
  EXPECT_EQ(NormaliseTypeName("array [1..3] of lreal"), "ARRAY[1..3]OFLREAL");
  const double values[] = {1.5, -2.25e-3};
  EXPECT_EQ(DecodeReals(EncodeReals(values)), (std::vector<double>{1.5, -2.25e-3}));
  // LREAL 1.5 is 0x3FF8000000000000, little-endian on the wire.
  EXPECT_EQ(EncodeReals(std::span(values, 1)), (Bytes{0, 0, 0, 0, 0, 0, 0xF8, 0x3F}));
  EXPECT_EQ(DecodeUdint(EncodeUdint(0xFFFFFFFF)), 0xFFFFFFFFu);
  EXPECT_TRUE(DecodeBool(Bytes{2}));
}

}  // namespace
}  // namespace hybridtest::transfer::ads
