// See ads_codec.h: framing, headers and the payloads of the commands. The sum commands,
// symbol entries and handle answers are in ads_codec_symbols.cc.
#include "hybridtest/transfer/ads/ads_codec.h"

#include <fmt/core.h>

#include <algorithm>
#include <cctype>

#include "hybridtest/common/error.h"

namespace hybridtest::transfer::ads {
namespace {

void PutAddress(std::vector<std::uint8_t>& out, const AmsAddress& a) {
  PutBytes(out, a.net_id.bytes);
  PutU16(out, a.port);
}

AmsAddress GetAddress(std::span<const std::uint8_t> in, std::size_t at) {
  AmsAddress a;
  std::copy_n(in.begin() + static_cast<std::ptrdiff_t>(at), 6, a.net_id.bytes.begin());
  a.port = GetU16(in, at + 6);
  return a;
}

}  // namespace

void NeedBytes(std::span<const std::uint8_t> in, std::size_t need, const char* what) {
  if (in.size() < need) {
    throw TransferError(fmt::format("garbled ADS {}: {} bytes, expected at least {}", what,
                                    in.size(), need));
  }
}

void PutBytes(std::vector<std::uint8_t>& out, std::span<const std::uint8_t> bytes) {
  out.insert(out.end(), bytes.begin(), bytes.end());
}

std::string AdsErrorName(std::uint32_t code) {
  static const std::pair<std::uint32_t, const char*> kNames[] = {
      {0x06, "target port not found: no ADS server on that AMS port"},
      {0x07, "target machine not found: no route to that AmsNetId"},
      {0x08, "unknown command id"},
      {0x700, "general device error"},
      {0x701, "service not supported by the server"},
      {0x702, "invalid index group"},
      {0x703, "invalid index offset"},
      {0x704, "reading or writing not permitted"},
      {0x705, "parameter size not correct"},
      {0x706, "invalid data values"},
      {0x707, "device not in ready state"},
      {0x708, "device busy"},
      {0x70A, "out of memory"},
      {0x70B, "invalid parameter values"},
      {0x710, "symbol not found"},
      {0x711, "symbol version invalid (the PLC program was changed: handles are void)"},
      {0x712, "server is in an invalid state"},
      {0x718, "device not initialised"},
      {0x719, "device timeout"},
      {0x71E, "request pending"},
      {0x71F, "request aborted"},
      {0x723, "access denied"},
      {0x740, "client error"},
      {0x745, "timeout elapsed"},
      {0x754, "invalid response received"},
  };
  for (const auto& [c, name] : kNames) {
    if (c == code) return fmt::format("0x{:X} ({})", code, name);
  }
  const char* range = code >= 0x740 ? "client error" : code >= 0x700 ? "device error"
                      : code >= 0x500 ? "router error" : "AMS error";
  return fmt::format("0x{:X} ({})", code, range);
}

std::string AdsStateName(std::uint16_t state) {
  static const char* kNames[] = {"INVALID", "IDLE", "RESET", "INIT", "START", "RUN", "STOP",
                                 "SAVECFG", "LOADCFG", "POWERFAILURE", "POWERGOOD", "ERROR",
                                 "SHUTDOWN", "SUSPEND", "RESUME", "CONFIG", "RECONFIG"};
  if (state < std::size(kNames)) return kNames[state];
  return fmt::format("state {}", state);
}

std::optional<AmsNetId> ParseAmsNetId(const std::string& text) {
  AmsNetId id;
  std::size_t at = 0;
  for (std::size_t i = 0; i < 6; ++i) {
    std::size_t end = at;
    while (end < text.size() && std::isdigit(static_cast<unsigned char>(text[end]))) ++end;
    if (end == at || end - at > 3) return std::nullopt;
    const int value = std::stoi(text.substr(at, end - at));
    if (value > 255) return std::nullopt;
    id.bytes[i] = static_cast<std::uint8_t>(value);
    if (i < 5) {
      if (end >= text.size() || text[end] != '.') return std::nullopt;
      ++end;
    }
    at = end;
  }
  if (at != text.size()) return std::nullopt;
  return id;
}

std::string FormatAmsNetId(const AmsNetId& id) {
  const auto& b = id.bytes;
  return fmt::format("{}.{}.{}.{}.{}.{}", b[0], b[1], b[2], b[3], b[4], b[5]);
}

void PutU16(std::vector<std::uint8_t>& out, std::uint16_t value) {
  out.push_back(static_cast<std::uint8_t>(value));
  out.push_back(static_cast<std::uint8_t>(value >> 8));
}

void PutU32(std::vector<std::uint8_t>& out, std::uint32_t value) {
  for (int shift = 0; shift < 32; shift += 8) out.push_back(static_cast<std::uint8_t>(value >> shift));
}

std::uint16_t GetU16(std::span<const std::uint8_t> in, std::size_t at) {
  NeedBytes(in, at + 2, "field");
  return static_cast<std::uint16_t>(in[at] | in[at + 1] << 8);
}

std::uint32_t GetU32(std::span<const std::uint8_t> in, std::size_t at) {
  NeedBytes(in, at + 4, "field");
  return std::uint32_t{in[at]} | std::uint32_t{in[at + 1]} << 8 | std::uint32_t{in[at + 2]} << 16 |
         std::uint32_t{in[at + 3]} << 24;
}

std::vector<std::uint8_t> EncodePacket(const AmsPacket& p) {
  std::vector<std::uint8_t> out;
  out.reserve(kPrefixSize + kHeaderSize + p.data.size());
  PutU16(out, kTcpAmsCommand);
  PutU32(out, static_cast<std::uint32_t>(kHeaderSize + p.data.size()));
  PutAddress(out, p.header.target);
  PutAddress(out, p.header.source);
  PutU16(out, static_cast<std::uint16_t>(p.header.command));
  PutU16(out, p.header.state_flags);
  PutU32(out, static_cast<std::uint32_t>(p.data.size()));
  PutU32(out, p.header.error);
  PutU32(out, p.header.invoke_id);
  PutBytes(out, p.data);
  return out;
}

std::vector<std::uint8_t> EncodeRouterMessage(std::uint16_t reserved,
                                              std::span<const std::uint8_t> data) {
  std::vector<std::uint8_t> out;
  PutU16(out, reserved);
  PutU32(out, static_cast<std::uint32_t>(data.size()));
  PutBytes(out, data);
  return out;
}

Prefix DecodePrefix(std::span<const std::uint8_t> six_bytes) {
  NeedBytes(six_bytes, kPrefixSize, "AMS/TCP prefix");
  Prefix p{GetU16(six_bytes, 0), GetU32(six_bytes, 2)};
  if (p.length > kMaxPacket) {
    throw TransferError(fmt::format("garbled AMS/TCP prefix: a packet of {} bytes announced, "
                                    "more than the {} accepted", p.length, kMaxPacket));
  }
  return p;
}

AmsPacket DecodePacket(std::span<const std::uint8_t> body) {
  NeedBytes(body, kHeaderSize, "AMS header");
  AmsPacket p;
  p.header.target = GetAddress(body, 0);
  p.header.source = GetAddress(body, 8);
  p.header.command = static_cast<Command>(GetU16(body, 16));
  p.header.state_flags = GetU16(body, 18);
  p.header.data_length = GetU32(body, 20);
  p.header.error = GetU32(body, 24);
  p.header.invoke_id = GetU32(body, 28);
  if (p.header.data_length != body.size() - kHeaderSize) {
    throw TransferError(fmt::format("garbled AMS header: data length {} in a packet of {} data "
                                    "bytes", p.header.data_length, body.size() - kHeaderSize));
  }
  p.data.assign(body.begin() + kHeaderSize, body.end());
  return p;
}

std::vector<std::uint8_t> ReadRequest(std::uint32_t group, std::uint32_t offset,
                                      std::uint32_t length) {
  std::vector<std::uint8_t> out;
  for (std::uint32_t v : {group, offset, length}) PutU32(out, v);
  return out;
}

std::vector<std::uint8_t> WriteRequest(std::uint32_t group, std::uint32_t offset,
                                       std::span<const std::uint8_t> data) {
  std::vector<std::uint8_t> out = ReadRequest(group, offset, static_cast<std::uint32_t>(data.size()));
  PutBytes(out, data);
  return out;
}

std::vector<std::uint8_t> ReadWriteRequest(std::uint32_t group, std::uint32_t offset,
                                           std::uint32_t read_length,
                                           std::span<const std::uint8_t> data) {
  std::vector<std::uint8_t> out = ReadRequest(group, offset, read_length);
  PutU32(out, static_cast<std::uint32_t>(data.size()));
  PutBytes(out, data);
  return out;
}

IndexRequest DecodeReadRequest(std::span<const std::uint8_t> payload) {
  NeedBytes(payload, 12, "Read request");
  return {GetU32(payload, 0), GetU32(payload, 4), GetU32(payload, 8), {}};
}

IndexRequest DecodeWriteRequest(std::span<const std::uint8_t> payload) {
  NeedBytes(payload, 12, "Write request");
  const std::uint32_t length = GetU32(payload, 8);
  NeedBytes(payload, 12 + std::size_t{length}, "Write request");
  return {GetU32(payload, 0), GetU32(payload, 4), 0,
          {payload.begin() + 12, payload.begin() + 12 + length}};
}

IndexRequest DecodeReadWriteRequest(std::span<const std::uint8_t> payload) {
  NeedBytes(payload, 16, "ReadWrite request");
  const std::uint32_t length = GetU32(payload, 12);
  NeedBytes(payload, 16 + std::size_t{length}, "ReadWrite request");
  return {GetU32(payload, 0), GetU32(payload, 4), GetU32(payload, 8),
          {payload.begin() + 16, payload.begin() + 16 + length}};
}

std::vector<std::uint8_t> EncodeDataResponse(std::uint32_t result,
                                             std::span<const std::uint8_t> data) {
  std::vector<std::uint8_t> out;
  PutU32(out, result);
  PutU32(out, static_cast<std::uint32_t>(data.size()));
  PutBytes(out, data);
  return out;
}

std::vector<std::uint8_t> EncodeResultResponse(std::uint32_t result) {
  std::vector<std::uint8_t> out;
  PutU32(out, result);
  return out;
}

DataResponse DecodeDataResponse(std::span<const std::uint8_t> payload) {
  NeedBytes(payload, 4, "response");
  DataResponse r{GetU32(payload, 0), {}};
  if (r.result != 0 && payload.size() < 8) return r;  // an error answer may stop at its result
  const std::uint32_t length = GetU32(payload, 4);
  NeedBytes(payload, 8 + std::size_t{length}, "response data");
  r.data.assign(payload.begin() + 8, payload.begin() + 8 + length);
  return r;
}

std::uint32_t DecodeResultResponse(std::span<const std::uint8_t> payload) {
  return GetU32(payload, 0);
}

std::vector<std::uint8_t> EncodeStateResponse(const StateResponse& r) {
  std::vector<std::uint8_t> out;
  PutU32(out, r.result);
  PutU16(out, r.ads_state);
  PutU16(out, r.device_state);
  return out;
}

StateResponse DecodeStateResponse(std::span<const std::uint8_t> payload) {
  StateResponse r{GetU32(payload, 0), 0, 0};
  if (r.result != 0) return r;
  r.ads_state = GetU16(payload, 4);
  r.device_state = GetU16(payload, 6);
  return r;
}

std::vector<std::uint8_t> EncodeDeviceInfo(const DeviceInfo& info) {
  std::vector<std::uint8_t> out;
  PutU32(out, info.result);
  out.push_back(info.major);
  out.push_back(info.minor);
  PutU16(out, info.build);
  std::array<std::uint8_t, 16> name{};
  std::copy_n(info.name.begin(), std::min<std::size_t>(info.name.size(), 15), name.begin());
  PutBytes(out, name);
  return out;
}

DeviceInfo DecodeDeviceInfo(std::span<const std::uint8_t> payload) {
  DeviceInfo info;
  info.result = GetU32(payload, 0);
  if (info.result != 0) return info;
  NeedBytes(payload, 24, "ReadDeviceInfo response");
  info.major = payload[4];
  info.minor = payload[5];
  info.build = GetU16(payload, 6);
  info.name = DataName(payload.subspan(8, 16));
  return info;
}

}  // namespace hybridtest::transfer::ads
