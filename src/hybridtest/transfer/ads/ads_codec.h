#pragma once
// The ADS/AMS wire format (Beckhoff TwinCAT), as a pure codec: bytes in, values out, no I/O.
// Written from the published protocol description (docs/ads.md, "The wire"); every integer is
// little-endian.
//
//   AMS/TCP prefix (6 bytes): reserved u16 (0: an AMS packet follows; 0x1000 port connect,
//     0x0001 port close, 0x1002 get local NetId: router messages), length u32 of what follows.
//   AMS header (32 bytes): target NetId (6) and port u16, source NetId (6) and port u16,
//     command id u16, state flags u16 (0x0004 request, 0x0005 response), data length u32,
//     error code u32, invoke id u32; then `data length` bytes of ADS payload.
//
// Payloads of the commands hybridtest uses (request → response; every response starts with
// the result u32):
//   Read       index group, index offset, length         → result, length, data
//   Write      index group, index offset, length, data   → result
//   ReadWrite  group, offset, read length, write length, data → result, length, data
//   ReadState  (empty)                                   → result, ADS state u16, device state u16
//   ReadDeviceInfo (empty)                               → result, major u8, minor u8,
//                                                           build u16, name (16 bytes)
// Sum commands (ReadWrite on 0xF080 read / 0xF081 write, index offset = number of
// sub-requests): the write data lists every sub-request's (group, offset, length) and then,
// for a sum write, their data; the answer holds one result u32 per sub-request, then (sum
// read) every sub-request's data in order.
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace hybridtest::transfer::ads {

inline constexpr std::uint16_t kAdsTcpPort = 48898;  // AMS/TCP (0xBF02)
inline constexpr std::uint16_t kPlcPort = 851;       // TwinCAT 3 PLC runtime 1 (TC2: 801)
inline constexpr std::size_t kPrefixSize = 6;        // AMS/TCP prefix [bytes]
inline constexpr std::size_t kHeaderSize = 32;       // AMS header [bytes]
inline constexpr std::uint32_t kMaxPacket = 1u << 20;  // largest packet either side accepts

// The AMS/TCP prefix's first field.
inline constexpr std::uint16_t kTcpAmsCommand = 0x0000;
inline constexpr std::uint16_t kTcpPortClose = 0x0001;
inline constexpr std::uint16_t kTcpPortConnect = 0x1000;
inline constexpr std::uint16_t kTcpGetLocalNetId = 0x1002;

enum class Command : std::uint16_t {
  kReadDeviceInfo = 1,
  kRead = 2,
  kWrite = 3,
  kReadState = 4,
  kWriteControl = 5,
  kAddNotification = 6,
  kDeleteNotification = 7,
  kNotification = 8,
  kReadWrite = 9,
};
inline constexpr std::uint16_t kFlagRequest = 0x0004;
inline constexpr std::uint16_t kFlagResponse = 0x0005;

// Reserved index groups.
inline constexpr std::uint32_t kGroupPlcData = 0x4040;  // a TwinCAT 3 PLC's variables (the emulator's GVL)
inline constexpr std::uint32_t kGroupHandleByName = 0xF003;    // ReadWrite name → handle
inline constexpr std::uint32_t kGroupValueByName = 0xF004;     // ReadWrite name → value
inline constexpr std::uint32_t kGroupValueByHandle = 0xF005;   // offset = handle
inline constexpr std::uint32_t kGroupReleaseHandle = 0xF006;   // Write handle
inline constexpr std::uint32_t kGroupSymbolInfoByName = 0xF009;  // ReadWrite name → entry
inline constexpr std::uint32_t kGroupSumRead = 0xF080;
inline constexpr std::uint32_t kGroupSumWrite = 0xF081;
inline constexpr std::uint32_t kGroupSumReadWrite = 0xF082;

// ADS states (ReadState).
inline constexpr std::uint16_t kStateRun = 5;
inline constexpr std::uint16_t kStateStop = 6;

// ADS error codes hybridtest names (0 = no error).
inline constexpr std::uint32_t kErrTargetPortNotFound = 0x06;
inline constexpr std::uint32_t kErrTargetMachineNotFound = 0x07;
inline constexpr std::uint32_t kErrDevice = 0x700;
inline constexpr std::uint32_t kErrServiceNotSupported = 0x701;
inline constexpr std::uint32_t kErrInvalidGroup = 0x702;
inline constexpr std::uint32_t kErrInvalidOffset = 0x703;
inline constexpr std::uint32_t kErrInvalidAccess = 0x704;
inline constexpr std::uint32_t kErrInvalidSize = 0x705;
inline constexpr std::uint32_t kErrInvalidData = 0x706;
inline constexpr std::uint32_t kErrNotReady = 0x707;
inline constexpr std::uint32_t kErrBusy = 0x708;
inline constexpr std::uint32_t kErrSymbolNotFound = 0x710;  // also: a handle it does not know
inline constexpr std::uint32_t kErrSymbolVersion = 0x711;
inline constexpr std::uint32_t kErrInvalidState = 0x712;
inline constexpr std::uint32_t kErrTimeout = 0x719;
inline constexpr std::uint32_t kErrClientTimeout = 0x745;

// "0x710 (symbol not found)"; an unknown code is given in hex with its range.
std::string AdsErrorName(std::uint32_t code);
// "RUN", "STOP", "CONFIG", … or "state N".
std::string AdsStateName(std::uint16_t state);

// ADS data type ids of a symbol entry (ADST_*) for the types of the profile.
inline constexpr std::uint32_t kTypeUint32 = 19;  // UDINT
inline constexpr std::uint32_t kTypeReal64 = 5;   // LREAL (also the element of an LREAL array)
inline constexpr std::uint32_t kTypeBit = 33;     // BOOL

struct AmsNetId {
  std::array<std::uint8_t, 6> bytes{};
  bool operator==(const AmsNetId&) const = default;
};
// "5.80.201.232.1.1": six numbers 0..255. nullopt if the text is not one.
std::optional<AmsNetId> ParseAmsNetId(const std::string& text);
std::string FormatAmsNetId(const AmsNetId& id);

struct AmsAddress {
  AmsNetId net_id;
  std::uint16_t port = 0;
  bool operator==(const AmsAddress&) const = default;
};

struct AmsHeader {
  AmsAddress target;
  AmsAddress source;
  Command command = Command::kRead;
  std::uint16_t state_flags = kFlagRequest;
  std::uint32_t data_length = 0;
  std::uint32_t error = 0;
  std::uint32_t invoke_id = 0;
};

// One AMS packet: the header and its ADS payload (header.data_length is set on encoding).
struct AmsPacket {
  AmsHeader header;
  std::vector<std::uint8_t> data;
};

// The whole packet, prefix included.
std::vector<std::uint8_t> EncodePacket(const AmsPacket& packet);
// A router message of the prefix `reserved` (e.g. kTcpPortConnect) with its data.
std::vector<std::uint8_t> EncodeRouterMessage(std::uint16_t reserved,
                                              std::span<const std::uint8_t> data);

struct Prefix {
  std::uint16_t reserved = 0;
  std::uint32_t length = 0;  // bytes that follow [bytes]
};
// Throws TransferError if the length exceeds kMaxPacket.
Prefix DecodePrefix(std::span<const std::uint8_t> six_bytes);
// The AMS packet of `body` (what follows a prefix with reserved 0). Throws TransferError if it
// is shorter than a header or its data length disagrees with its size.
AmsPacket DecodePacket(std::span<const std::uint8_t> body);

// ---- ADS payloads -------------------------------------------------------------------------

// Little-endian helpers over a byte vector.
void PutU16(std::vector<std::uint8_t>& out, std::uint16_t value);
void PutU32(std::vector<std::uint8_t>& out, std::uint32_t value);
void PutBytes(std::vector<std::uint8_t>& out, std::span<const std::uint8_t> bytes);
std::uint16_t GetU16(std::span<const std::uint8_t> in, std::size_t at);  // throws if short
std::uint32_t GetU32(std::span<const std::uint8_t> in, std::size_t at);
// Throws TransferError "garbled ADS <what>" unless `in` holds at least `need` bytes.
void NeedBytes(std::span<const std::uint8_t> in, std::size_t need, const char* what);

std::vector<std::uint8_t> ReadRequest(std::uint32_t group, std::uint32_t offset,
                                      std::uint32_t length);
std::vector<std::uint8_t> WriteRequest(std::uint32_t group, std::uint32_t offset,
                                       std::span<const std::uint8_t> data);
std::vector<std::uint8_t> ReadWriteRequest(std::uint32_t group, std::uint32_t offset,
                                           std::uint32_t read_length,
                                           std::span<const std::uint8_t> data);

// A request as a server sees it (Read: data empty; Write: read_length 0).
struct IndexRequest {
  std::uint32_t group = 0, offset = 0, read_length = 0;
  std::vector<std::uint8_t> data;
};
// Throws TransferError on a payload shorter than its fields say.
IndexRequest DecodeReadRequest(std::span<const std::uint8_t> payload);
IndexRequest DecodeWriteRequest(std::span<const std::uint8_t> payload);
IndexRequest DecodeReadWriteRequest(std::span<const std::uint8_t> payload);

// A response's result and data (Read, ReadWrite: result, length, data; Write: result alone).
struct DataResponse {
  std::uint32_t result = 0;
  std::vector<std::uint8_t> data;
};
std::vector<std::uint8_t> EncodeDataResponse(std::uint32_t result,
                                             std::span<const std::uint8_t> data);
std::vector<std::uint8_t> EncodeResultResponse(std::uint32_t result);
// Throws TransferError on a short or inconsistent payload.
DataResponse DecodeDataResponse(std::span<const std::uint8_t> payload);
std::uint32_t DecodeResultResponse(std::span<const std::uint8_t> payload);

struct StateResponse {
  std::uint32_t result = 0;
  std::uint16_t ads_state = 0, device_state = 0;
};
std::vector<std::uint8_t> EncodeStateResponse(const StateResponse& r);
StateResponse DecodeStateResponse(std::span<const std::uint8_t> payload);

struct DeviceInfo {
  std::uint32_t result = 0;
  std::uint8_t major = 0, minor = 0;
  std::uint16_t build = 0;
  std::string name;  // at most 16 bytes on the wire
};
std::vector<std::uint8_t> EncodeDeviceInfo(const DeviceInfo& info);
DeviceInfo DecodeDeviceInfo(std::span<const std::uint8_t> payload);

// ---- Sum commands -------------------------------------------------------------------------

// One sub-request of a sum read or write.
struct SubRequest {
  std::uint32_t group = 0, offset = 0, length = 0;
  std::vector<std::uint8_t> data;  // sum write only (length bytes)
};
// The ReadWrite payload of a sum read (0xF080) / sum write (0xF081) of `items`.
std::vector<std::uint8_t> SumReadRequest(std::span<const SubRequest> items);
std::vector<std::uint8_t> SumWriteRequest(std::span<const SubRequest> items);
// The server's side: the sub-requests of a sum read / write (count from the index offset).
// Throws TransferError if the data does not hold them.
std::vector<SubRequest> DecodeSumRead(std::uint32_t count, std::span<const std::uint8_t> data);
std::vector<SubRequest> DecodeSumWrite(std::uint32_t count, std::span<const std::uint8_t> data);
// The read data of a sum answer: results (one per sub-request), then (sum read) the data of
// each sub-request at its requested length.
std::vector<std::uint8_t> EncodeSumReadAnswer(std::span<const DataResponse> answers,
                                              std::span<const SubRequest> items);
std::vector<std::uint8_t> EncodeSumWriteAnswer(std::span<const std::uint32_t> results);
// The client's side: one DataResponse per sub-request of lengths `lengths` (sum read), or
// one result each (sum write). Throws TransferError on a short answer.
std::vector<DataResponse> DecodeSumReadAnswer(std::span<const std::uint8_t> data,
                                              std::span<const std::uint32_t> lengths);
std::vector<std::uint32_t> DecodeSumWriteAnswer(std::span<const std::uint8_t> data,
                                                std::size_t count);

// ---- Symbols ------------------------------------------------------------------------------

// A symbol's entry (0xF009): where it lives, its size [bytes], its ADS type id and IEC type
// name ("ARRAY [1..2] OF LREAL"), and for an array its dimensions (start index, length).
struct SymbolInfo {
  std::uint32_t group = 0, offset = 0, size = 0, data_type = 0;
  std::uint16_t flags = 0;
  std::string name, type, comment;
  std::vector<std::pair<std::int32_t, std::uint32_t>> array;  // (start, length) per dimension
};
// The entry as the read data of 0xF009: entry length u32, group, offset, size, data type u32,
// flags u16, array dimensions u16, name/type/comment lengths u16, the three NUL-terminated
// strings, then (start i32, length u32) per dimension.
std::vector<std::uint8_t> EncodeSymbolInfo(const SymbolInfo& s);
SymbolInfo DecodeSymbolInfo(std::span<const std::uint8_t> data);  // throws TransferError

// The write data of a request by name (0xF003, 0xF009): the name and a NUL.
std::vector<std::uint8_t> NameData(const std::string& name);
// The name of such a request (up to the first NUL).
std::string DataName(std::span<const std::uint8_t> data);

// The answer to 0xF003: the handle alone (read length 4), or (read length > 4, TwinCAT
// 3.1.4024 and later) handle, size u32, type decoration u32, type name length u16, type name.
struct HandleAnswer {
  std::uint32_t handle = 0;
  std::optional<std::uint32_t> size;
  std::string type;
};
std::vector<std::uint8_t> EncodeHandleAnswer(const HandleAnswer& a, std::uint32_t read_length);
HandleAnswer DecodeHandleAnswer(std::span<const std::uint8_t> data);

// IEC 61131-3 type name normalised for comparison: upper case, no blanks.
std::string NormaliseTypeName(const std::string& type);

}  // namespace hybridtest::transfer::ads
