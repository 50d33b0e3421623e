// See wire.h.
#include "hybridtest/transfer/openfresco/wire.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "hybridtest/common/error.h"

namespace hybridtest::transfer::openfresco {
namespace {

void PutInt(std::vector<std::uint8_t>& out, std::int32_t value) {
  const std::size_t at = out.size();
  out.resize(at + 4);
  std::memcpy(out.data() + at, &value, 4);
}

}  // namespace

std::string ActionName(int action) {
  switch (action) {
    case 1: return "open";
    case 2: return "setup";
    case 3: return "setTrialResponse";
    case 4: return "execute";
    case 5: return "commitState";
    case 6: return "getDaqResponse";
    case 7: return "getDisp";
    case 8: return "getVel";
    case 9: return "getAccel";
    case 10: return "getForce";
    case 11: return "getTime";
    case 12: return "getInitialStiff";
    case 13: return "getTangentStiff";
    case 14: return "getDamp";
    case 15: return "getMass";
    case 98: return "shutdown";
    case 99: return "DIE";
    default: return "unknown";
  }
}

Header PlainHeader(int n) {
  Header h;
  h.size_ctrl = {n, n, n, 0, 0};
  h.size_daq = {0, 0, 0, n, 0};
  h.data_size = std::max({kDefaultDataSize, 3 * n + 2, n * n});
  return h;
}

std::vector<std::uint8_t> EncodeHeader(const Header& header) {
  std::vector<std::uint8_t> out;
  out.reserve(kHeaderBytes);
  for (const std::int32_t v : header.size_ctrl) PutInt(out, v);
  for (const std::int32_t v : header.size_daq) PutInt(out, v);
  PutInt(out, header.data_size);
  return out;
}

Header DecodeHeader(std::span<const std::uint8_t> bytes) {
  if (bytes.size() != kHeaderBytes) {
    throw TransferError(fmt::format("OpenFresco header: {} bytes, expected {} (11 int32)",
                                    bytes.size(), kHeaderBytes));
  }
  std::int32_t words[11];
  std::memcpy(words, bytes.data(), kHeaderBytes);
  Header h;
  std::copy(words, words + 5, h.size_ctrl.begin());
  std::copy(words + 5, words + 10, h.size_daq.begin());
  h.data_size = words[10];
  return h;
}

void ValidateHeader(const Header& h) {
  static constexpr const char* kNames[5] = {"disp", "vel", "accel", "force", "time"};
  const auto fail = [&](const std::string& why) {
    throw TransferError(fmt::format(
        "OpenFresco header {{{},{},{},{},{}, {},{},{},{},{}, {}}}: {}", h.size_ctrl[0],
        h.size_ctrl[1], h.size_ctrl[2], h.size_ctrl[3], h.size_ctrl[4], h.size_daq[0],
        h.size_daq[1], h.size_daq[2], h.size_daq[3], h.size_daq[4], h.data_size, why));
  };
  long ctrl = 0;
  long daq = 0;
  for (int i = 0; i < 5; ++i) {
    if (h.size_ctrl[i] < 0 || h.size_ctrl[i] > kMaxDofs) {
      fail(fmt::format("sizeCtrl {} = {} is outside [0, {}]", kNames[i], h.size_ctrl[i],
                       kMaxDofs));
    }
    if (h.size_daq[i] < 0 || h.size_daq[i] > kMaxDofs) {
      fail(fmt::format("sizeDaq {} = {} is outside [0, {}]", kNames[i], h.size_daq[i], kMaxDofs));
    }
    ctrl += h.size_ctrl[i];
    daq += h.size_daq[i];
  }
  const long n = h.dofs();
  if (n < 1) fail("sizeCtrl disp = 0: this server controls displacement, expected n >= 1");
  if (h.data_size < 1 || h.data_size > kMaxDataSize) {
    fail(fmt::format("dataSize = {} is outside [1, {}]", h.data_size, kMaxDataSize));
  }
  const long needed = std::max({1 + ctrl, n * n, daq});
  if (h.data_size < needed) {
    fail(fmt::format("dataSize = {} is too small: the session's longest message needs {} "
                     "words (max of 1 + Σ sizeCtrl, n², Σ sizeDaq)",
                     h.data_size, needed));
  }
}

std::vector<std::uint8_t> EncodeMessage(std::span<const double> values, int data_size) {
  if (data_size < 0 || values.size() > static_cast<std::size_t>(data_size)) {
    throw TransferError(fmt::format("OpenFresco message: {} values do not fit dataSize = {}",
                                    values.size(), data_size));
  }
  std::vector<std::uint8_t> out(static_cast<std::size_t>(data_size) * 8, 0);
  if (!values.empty()) std::memcpy(out.data(), values.data(), values.size() * 8);
  return out;
}

std::vector<double> DecodeMessage(std::span<const std::uint8_t> bytes) {
  if (bytes.size() % 8 != 0) {
    throw TransferError(fmt::format("OpenFresco message: {} bytes is not a whole number of "
                                    "float64 words", bytes.size()));
  }
  std::vector<double> out(bytes.size() / 8);
  if (!out.empty()) std::memcpy(out.data(), bytes.data(), bytes.size());
  return out;
}

int ActionOf(std::span<const double> message) {
  if (message.empty()) return -1;
  const double a = message[0];
  if (!(a >= 0.0 && a <= 1000.0) || a != std::floor(a)) return -1;
  return static_cast<int>(a);
}

std::vector<std::uint8_t> EncodeTokenPreamble(const std::string& token) {
  if (token.empty() || token.size() > static_cast<std::size_t>(kMaxTokenBytes)) {
    throw TransferError(fmt::format("OpenFresco token preamble: a token of {} bytes; expected "
                                    "1 to {} bytes", token.size(), kMaxTokenBytes));
  }
  // One allocation and memcpy: GCC 12 warns falsely on vector::insert into a fresh vector.
  std::vector<std::uint8_t> out(8 + token.size());
  const std::int32_t words[2] = {kTokenMagic, static_cast<std::int32_t>(token.size())};
  std::memcpy(out.data(), words, 8);
  std::memcpy(out.data() + 8, token.data(), token.size());
  return out;
}

namespace {

std::int32_t IntAt(std::span<const std::uint8_t> bytes, std::size_t at) {
  std::int32_t v = 0;
  std::memcpy(&v, bytes.data() + at, 4);
  return v;
}

}  // namespace

std::size_t OpeningSize(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < 4) return 4;
  if (IntAt(bytes, 0) != kTokenMagic) return kHeaderBytes;
  if (bytes.size() < 8) return 8;
  const std::int32_t n = IntAt(bytes, 4);
  if (n < 1 || n > kMaxTokenBytes) {
    throw TransferError(fmt::format("OpenFresco token preamble announces {} bytes; expected 1 "
                                    "to {}", n, kMaxTokenBytes));
  }
  return 8 + static_cast<std::size_t>(n) + kHeaderBytes;
}

Opening DecodeOpening(std::span<const std::uint8_t> bytes) {
  const std::size_t size = OpeningSize(bytes);
  if (bytes.size() != size) {
    throw TransferError(fmt::format("OpenFresco opening: {} bytes; the first bytes announce {} "
                                    "(token preamble, then the 44-byte header)", bytes.size(),
                                    size));
  }
  Opening opening;
  std::size_t at = 0;
  if (IntAt(bytes, 0) == kTokenMagic) {
    const auto n = static_cast<std::size_t>(IntAt(bytes, 4));
    opening.has_token = true;
    opening.token.assign(reinterpret_cast<const char*>(bytes.data() + 8), n);
    at = 8 + n;
  }
  opening.header = DecodeHeader(bytes.subspan(at, kHeaderBytes));
  return opening;
}

}  // namespace hybridtest::transfer::openfresco
