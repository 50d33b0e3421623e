// See ads_codec.h: the sum commands, symbol entries, names and handle answers.
#include <fmt/core.h>

#include <algorithm>
#include <cctype>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/ads/ads_codec.h"

namespace hybridtest::transfer::ads {
namespace {

// The sub-request headers (12 bytes each) at the start of a sum request's data.
std::vector<SubRequest> SubHeaders(std::uint32_t count, std::span<const std::uint8_t> data) {
  NeedBytes(data, std::size_t{count} * 12, "sum command");
  std::vector<SubRequest> items(count);
  for (std::size_t i = 0; i < count; ++i) {
    items[i].group = GetU32(data, 12 * i);
    items[i].offset = GetU32(data, 12 * i + 4);
    items[i].length = GetU32(data, 12 * i + 8);
  }
  return items;
}

std::vector<std::uint8_t> SumRequest(std::span<const SubRequest> items, bool write) {
  std::vector<std::uint8_t> headers;
  std::uint32_t read_length = 0;
  for (const SubRequest& s : items) {
    PutU32(headers, s.group);
    PutU32(headers, s.offset);
    PutU32(headers, s.length);
    read_length += 4 + (write ? 0 : s.length);
  }
  if (write) {
    for (const SubRequest& s : items) PutBytes(headers, s.data);
  }
  return ReadWriteRequest(write ? kGroupSumWrite : kGroupSumRead,
                          static_cast<std::uint32_t>(items.size()), read_length, headers);
}

}  // namespace

std::vector<std::uint8_t> SumReadRequest(std::span<const SubRequest> items) {
  return SumRequest(items, false);
}

std::vector<std::uint8_t> SumWriteRequest(std::span<const SubRequest> items) {
  return SumRequest(items, true);
}

std::vector<SubRequest> DecodeSumRead(std::uint32_t count, std::span<const std::uint8_t> data) {
  return SubHeaders(count, data);
}

std::vector<SubRequest> DecodeSumWrite(std::uint32_t count, std::span<const std::uint8_t> data) {
  std::vector<SubRequest> items = SubHeaders(count, data);
  std::size_t at = std::size_t{count} * 12;
  for (SubRequest& s : items) {
    NeedBytes(data, at + s.length, "sum write data");
    s.data.assign(data.begin() + static_cast<std::ptrdiff_t>(at),
                  data.begin() + static_cast<std::ptrdiff_t>(at + s.length));
    at += s.length;
  }
  return items;
}

std::vector<std::uint8_t> EncodeSumReadAnswer(std::span<const DataResponse> answers,
                                              std::span<const SubRequest> items) {
  std::vector<std::uint8_t> out;
  for (const DataResponse& a : answers) PutU32(out, a.result);
  for (std::size_t i = 0; i < answers.size(); ++i) {
    std::vector<std::uint8_t> data = answers[i].data;
    data.resize(items[i].length);  // a failed sub-request keeps its place, zero-filled
    PutBytes(out, data);
  }
  return out;
}

std::vector<std::uint8_t> EncodeSumWriteAnswer(std::span<const std::uint32_t> results) {
  std::vector<std::uint8_t> out;
  for (std::uint32_t r : results) PutU32(out, r);
  return out;
}

std::vector<DataResponse> DecodeSumReadAnswer(std::span<const std::uint8_t> data,
                                              std::span<const std::uint32_t> lengths) {
  std::size_t need = 4 * lengths.size();
  for (std::uint32_t l : lengths) need += l;
  NeedBytes(data, need, "sum read answer");
  std::vector<DataResponse> out(lengths.size());
  std::size_t at = 4 * lengths.size();
  for (std::size_t i = 0; i < lengths.size(); ++i) {
    out[i].result = GetU32(data, 4 * i);
    out[i].data.assign(data.begin() + static_cast<std::ptrdiff_t>(at),
                       data.begin() + static_cast<std::ptrdiff_t>(at + lengths[i]));
    at += lengths[i];
  }
  return out;
}

std::vector<std::uint32_t> DecodeSumWriteAnswer(std::span<const std::uint8_t> data,
                                                std::size_t count) {
  NeedBytes(data, 4 * count, "sum write answer");
  std::vector<std::uint32_t> out(count);
  for (std::size_t i = 0; i < count; ++i) out[i] = GetU32(data, 4 * i);
  return out;
}

std::vector<std::uint8_t> EncodeSymbolInfo(const SymbolInfo& s) {
  std::vector<std::uint8_t> body;
  for (std::uint32_t v : {s.group, s.offset, s.size, s.data_type}) PutU32(body, v);
  PutU16(body, s.flags);
  PutU16(body, static_cast<std::uint16_t>(s.array.size()));
  for (const std::string* text : {&s.name, &s.type, &s.comment}) {
    PutU16(body, static_cast<std::uint16_t>(text->size()));
  }
  for (const std::string* text : {&s.name, &s.type, &s.comment}) {
    PutBytes(body, NameData(*text));
  }
  for (const auto& [start, length] : s.array) {
    PutU32(body, static_cast<std::uint32_t>(start));
    PutU32(body, length);
  }
  std::vector<std::uint8_t> out;
  PutU32(out, static_cast<std::uint32_t>(4 + body.size()));
  PutBytes(out, body);
  return out;
}

SymbolInfo DecodeSymbolInfo(std::span<const std::uint8_t> data) {
  NeedBytes(data, 34, "symbol entry");
  SymbolInfo s;
  s.group = GetU32(data, 4);
  s.offset = GetU32(data, 8);
  s.size = GetU32(data, 12);
  s.data_type = GetU32(data, 16);
  s.flags = GetU16(data, 20);
  const std::uint16_t dims = GetU16(data, 22);
  std::size_t at = 30;
  for (std::size_t i = 0; i < 3; ++i) {
    const std::size_t length = GetU16(data, 24 + 2 * i);
    NeedBytes(data, at + length + 1, "symbol entry's strings");
    std::string text(data.begin() + static_cast<std::ptrdiff_t>(at),
                     data.begin() + static_cast<std::ptrdiff_t>(at + length));
    (i == 0 ? s.name : i == 1 ? s.type : s.comment) = std::move(text);
    at += length + 1;
  }
  for (std::size_t i = 0; i < dims; ++i) {
    s.array.emplace_back(static_cast<std::int32_t>(GetU32(data, at)), GetU32(data, at + 4));
    at += 8;
  }
  return s;
}

std::vector<std::uint8_t> NameData(const std::string& name) {
  std::vector<std::uint8_t> out(name.begin(), name.end());
  out.push_back(0);
  return out;
}

std::string DataName(std::span<const std::uint8_t> data) {
  const auto end = std::find(data.begin(), data.end(), std::uint8_t{0});
  return std::string(data.begin(), end);
}

std::vector<std::uint8_t> EncodeHandleAnswer(const HandleAnswer& a, std::uint32_t read_length) {
  std::vector<std::uint8_t> out;
  PutU32(out, a.handle);
  if (read_length <= 4) return out;
  PutU32(out, a.size.value_or(0));
  PutU32(out, 0);  // type decoration
  PutU16(out, static_cast<std::uint16_t>(a.type.size()));
  PutBytes(out, NameData(a.type));
  return out;
}

HandleAnswer DecodeHandleAnswer(std::span<const std::uint8_t> data) {
  HandleAnswer a{GetU32(data, 0), std::nullopt, {}};
  if (data.size() < 14) return a;
  a.size = GetU32(data, 4);
  const std::size_t length = GetU16(data, 12);
  NeedBytes(data, 14 + length, "handle answer's type name");
  a.type.assign(data.begin() + 14, data.begin() + 14 + static_cast<std::ptrdiff_t>(length));
  return a;
}

std::string NormaliseTypeName(const std::string& type) {
  std::string out;
  for (char c : type) {
    if (!std::isspace(static_cast<unsigned char>(c))) {
      out.push_back(static_cast<char>(std::toupper(static_cast<unsigned char>(c))));
    }
  }
  return out;
}

}  // namespace hybridtest::transfer::ads
