// See ads_profile.h.
#include "hybridtest/transfer/ads/ads_profile.h"

#include <fmt/core.h>

#include <bit>
#include <cstring>

#include "hybridtest/transfer/ads/ads_codec.h"

namespace hybridtest::transfer::ads {
namespace {

struct RoleText {
  const char* key;
  const char* symbol;
};
constexpr RoleText kRoles[kNumRoles] = {
    {"command", "fCommand"}, {"sequence", "nCommandSeq"}, {"position", "fPosition"},
    {"force", "fForce"},     {"ack", "nAckSeq"},          {"enable", "bEnable"},
    {"hold", "bHold"},       {"enabled", "bEnabled"},     {"fault", "bFault"},
    {"holding", "bHolding"}, {"heartbeat", "nHeartbeat"},
};

}  // namespace

const char* RoleKey(Role role) { return kRoles[role].key; }

std::string DefaultSymbol(Role role) { return std::string("GVL_Hybrid.") + kRoles[role].symbol; }

ExpectedSymbol Expected(Role role, int actuators) {
  const bool writes = role == kCommand || role == kSequence || role == kEnable ||
                      role == kHold || role == kHeartbeat;
  switch (role) {
    case kCommand:
    case kPosition:
    case kForce:
      return {fmt::format("ARRAY [1..{}] OF LREAL", actuators),
              static_cast<std::uint32_t>(8 * actuators), writes};
    case kSequence:
    case kAck:
    case kHeartbeat:
      return {"UDINT", 4, writes};
    default:
      return {"BOOL", 1, writes};
  }
}

AdsProfile DefaultProfile(int actuators) {
  AdsProfile p;
  for (std::size_t r = 0; r < kNumRoles; ++r) p.symbols[r] = DefaultSymbol(static_cast<Role>(r));
  p.actuators = actuators;
  return p;
}

std::vector<std::uint8_t> EncodeReals(std::span<const double> values) {
  std::vector<std::uint8_t> out;
  for (double v : values) {
    const auto bits = std::bit_cast<std::uint64_t>(v);
    PutU32(out, static_cast<std::uint32_t>(bits));
    PutU32(out, static_cast<std::uint32_t>(bits >> 32));
  }
  return out;
}

std::vector<double> DecodeReals(std::span<const std::uint8_t> bytes) {
  std::vector<double> out;
  for (std::size_t at = 0; at + 8 <= bytes.size(); at += 8) {
    const std::uint64_t bits = std::uint64_t{GetU32(bytes, at)} | std::uint64_t{GetU32(bytes, at + 4)} << 32;
    out.push_back(std::bit_cast<double>(bits));
  }
  return out;
}

std::vector<std::uint8_t> EncodeUdint(std::uint32_t value) {
  std::vector<std::uint8_t> out;
  PutU32(out, value);
  return out;
}

std::vector<std::uint8_t> EncodeBool(bool value) { return {static_cast<std::uint8_t>(value)}; }

std::uint32_t DecodeUdint(std::span<const std::uint8_t> bytes) { return GetU32(bytes, 0); }

bool DecodeBool(std::span<const std::uint8_t> bytes) { return !bytes.empty() && bytes[0] != 0; }

}  // namespace hybridtest::transfer::ads
