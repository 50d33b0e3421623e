// See ads_plc_image.h.
#include "hybridtest/transfer/ads/ads_plc_image.h"

#include <algorithm>

namespace hybridtest::transfer::ads {

PlcImage::PlcImage(const AdsProfile& profile) {
  std::uint32_t offset = 0;
  for (std::size_t r = 0; r < kNumRoles; ++r) {
    const auto role = static_cast<Role>(r);
    const ExpectedSymbol e = Expected(role, profile.actuators);
    SymbolInfo s;
    s.group = kGroupPlcData;
    s.offset = offset;
    s.size = e.size;
    s.name = profile.symbols[r];
    s.type = e.type;
    if (role == kCommand || role == kPosition || role == kForce) {
      s.data_type = kTypeReal64;
      s.array = {{1, static_cast<std::uint32_t>(profile.actuators)}};
      s.comment = role == kForce ? "[" + profile.units.force_name + "]"
                                 : "[" + profile.units.length_name + "]";
    } else {
      s.data_type = e.size == 4 ? kTypeUint32 : kTypeBit;
    }
    symbols_.push_back(s);
    offset += (e.size + 7) / 8 * 8;  // each variable 8-byte aligned, as TwinCAT lays out LREALs
  }
  memory_.assign(offset, 0);
}

std::vector<double> PlcImage::Reals(Role role) const {
  const SymbolInfo& s = symbols_[role];
  return DecodeReals(std::span(memory_).subspan(s.offset, s.size));
}

void PlcImage::SetReals(Role role, std::span<const double> values) {
  const std::vector<std::uint8_t> bytes = EncodeReals(values);
  std::copy_n(bytes.begin(), std::min<std::size_t>(bytes.size(), symbols_[role].size),
              memory_.begin() + symbols_[role].offset);
}

std::uint32_t PlcImage::Udint(Role role) const {
  return DecodeUdint(std::span(memory_).subspan(symbols_[role].offset, 4));
}

void PlcImage::SetUdint(Role role, std::uint32_t value) {
  const std::vector<std::uint8_t> bytes = EncodeUdint(value);
  std::copy(bytes.begin(), bytes.end(), memory_.begin() + symbols_[role].offset);
}

bool PlcImage::Bool(Role role) const { return memory_[symbols_[role].offset] != 0; }

void PlcImage::SetBool(Role role, bool value) {
  memory_[symbols_[role].offset] = static_cast<std::uint8_t>(value);
}

Role PlcImage::At(std::uint32_t offset, std::uint32_t length) const {
  for (std::size_t r = 0; r < kNumRoles; ++r) {
    const SymbolInfo& s = symbols_[r];
    if (offset >= s.offset && std::uint64_t{offset} + length <= std::uint64_t{s.offset} + s.size) {
      return static_cast<Role>(r);
    }
  }
  return kNumRoles;
}

Role PlcImage::ByName(const std::string& name) const {
  const std::string wanted = NormaliseTypeName(name);  // upper case, no blanks
  for (std::size_t r = 0; r < kNumRoles; ++r) {
    if (NormaliseTypeName(symbols_[r].name) == wanted) return static_cast<Role>(r);
  }
  return kNumRoles;
}

DataResponse PlcImage::Read(std::uint32_t group, std::uint32_t offset,
                            std::uint32_t length) const {
  std::uint32_t start = offset;
  if (group == kGroupValueByHandle) {
    const auto h = handles_.find(offset);
    if (h == handles_.end()) return {kErrSymbolNotFound, {}};
    const SymbolInfo& s = symbols_[h->second.role];
    if (length != s.size) return {kErrInvalidSize, {}};
    start = s.offset;
  } else if (group == kGroupPlcData) {
    if (At(offset, length) == kNumRoles) return {kErrInvalidOffset, {}};
  } else {
    return {kErrInvalidGroup, {}};
  }
  return {0, {memory_.begin() + start, memory_.begin() + start + length}};
}

std::uint32_t PlcImage::Write(std::uint32_t group, std::uint32_t offset,
                              std::span<const std::uint8_t> data, int owner) {
  std::uint32_t start = offset;
  if (group == kGroupReleaseHandle) {
    if (data.size() != 4) return kErrInvalidSize;
    const auto h = handles_.find(GetU32(data, 0));
    if (h == handles_.end() || h->second.owner != owner) return kErrSymbolNotFound;
    handles_.erase(h);
    return 0;
  }
  if (group == kGroupValueByHandle) {
    const auto h = handles_.find(offset);
    if (h == handles_.end()) return kErrSymbolNotFound;
    const SymbolInfo& s = symbols_[h->second.role];
    if (data.size() != s.size) return kErrInvalidSize;
    start = s.offset;
  } else if (group == kGroupPlcData) {
    if (At(offset, static_cast<std::uint32_t>(data.size())) == kNumRoles) return kErrInvalidOffset;
  } else {
    return kErrInvalidGroup;
  }
  std::copy(data.begin(), data.end(), memory_.begin() + start);
  return 0;
}

DataResponse PlcImage::ReadWrite(std::uint32_t group, std::uint32_t /*offset*/,
                                 std::uint32_t read_length, std::span<const std::uint8_t> data,
                                 int owner) {
  if (group != kGroupHandleByName && group != kGroupSymbolInfoByName &&
      group != kGroupValueByName) {
    return {kErrServiceNotSupported, {}};
  }
  const Role role = ByName(DataName(data));
  if (role == kNumRoles) return {kErrSymbolNotFound, {}};
  const SymbolInfo& s = symbols_[role];
  std::vector<std::uint8_t> answer;
  if (group == kGroupSymbolInfoByName) {
    answer = EncodeSymbolInfo(s);
  } else if (group == kGroupValueByName) {
    answer.assign(memory_.begin() + s.offset, memory_.begin() + s.offset + s.size);
  } else {
    const std::uint32_t handle = next_handle_++;
    handles_[handle] = {role, owner};
    answer = EncodeHandleAnswer({handle, s.size, s.type}, read_length);
  }
  if (answer.size() > read_length) return {kErrInvalidSize, {}};
  return {0, std::move(answer)};
}

void PlcImage::ReleaseAll(int owner) {
  std::erase_if(handles_, [owner](const auto& h) { return h.second.owner == owner; });
}

}  // namespace hybridtest::transfer::ads
