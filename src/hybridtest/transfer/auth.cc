// See auth.h.
#include "hybridtest/transfer/auth.h"

#include <arpa/inet.h>
#include <fmt/core.h>
#include <netinet/in.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <fstream>

#include "hybridtest/common/error.h"
#include "hybridtest/common/input_file.h"
#include "hybridtest/transfer/socket.h"

namespace hybridtest::transfer {
namespace {
constexpr std::size_t kMaxTokenFileBytes = 64 * 1024;  // Unit: [bytes]
}  // namespace

bool TokensEqual(std::string_view a, std::string_view b) noexcept {
  // Every byte of the longer token is visited; the result is accumulated without branches.
  const std::size_t n = a.size() > b.size() ? a.size() : b.size();
  unsigned diff = a.size() == b.size() ? 0u : 1u;
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned char x = i < a.size() ? static_cast<unsigned char>(a[i]) : 0;
    const unsigned char y = i < b.size() ? static_cast<unsigned char>(b[i]) : 0;
    diff |= static_cast<unsigned>(x ^ y);
  }
  // Keep the compiler from turning the loop into an early-exit comparison.
  volatile unsigned result = diff;
  return result == 0;
}

std::string ReadTokenFile(const std::string& path, const std::string& where) {
  // Regular files only (a FIFO would block for ever); a token file is one short line.
  std::string token = ReadInputFile(path, where, "token file", kMaxTokenFileBytes);
  if (const auto eol = token.find_first_of("\r\n"); eol != std::string::npos) token.resize(eol);
  while (!token.empty() && (token.back() == ' ' || token.back() == '\t')) token.pop_back();
  if (token.size() > kMaxTokenBytes) {
    throw ConfigError(fmt::format("{} = '{}': the token is longer than {} bytes", where, path,
                                  kMaxTokenBytes));
  }
  if (token.empty()) {
    throw ConfigError(fmt::format("{} = '{}': the token file is empty; write the shared token "
                                  "on its first line", where, path));
  }
  return token;
}

std::string TokenFromEnvironment() {
  const char* value = std::getenv(kTokenEnvironmentVariable);
  return value == nullptr ? std::string() : std::string(value);
}

namespace {

bool OnlyWhitespace(const std::string& token) {
  return std::all_of(token.begin(), token.end(), [](char c) {
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
  });
}

}  // namespace

void CheckBindPolicy(const std::string& host, std::uint16_t port, const std::string& token,
                     const std::string& server) {
  if (!token.empty() && OnlyWhitespace(token)) {
    throw ConfigError(fmt::format(
        "refusing to serve {} on {}:{}: the token is only whitespace ({} bytes), which is no "
        "secret; write a random token of at least {} bytes in the token file (--token-file) or "
        "{}, e.g. from `head -c 24 /dev/urandom | base64`",
        server, host, port, token.size(), kMinRemoteTokenBytes, kTokenEnvironmentVariable));
  }
  if (IsLoopbackHost(host)) return;
  if (token.empty()) {
    throw ConfigError(fmt::format(
        "refusing to serve {} on {}:{} without a token: a non-loopback address lets anyone on "
        "the network move the actuator; set a shared token of at least {} bytes (--token-file "
        "or {}) or listen on 127.0.0.1 (and tunnel, e.g. ssh -L)",
        server, host, port, kMinRemoteTokenBytes, kTokenEnvironmentVariable));
  }
  if (token.size() < kMinRemoteTokenBytes) {
    throw ConfigError(fmt::format(
        "refusing to serve {} on {}:{} with a token of {} bytes: off loopback the token must "
        "have at least {} bytes so that it cannot be guessed; write a longer random token in "
        "the token file (--token-file) or {}, e.g. from `head -c 24 /dev/urandom | base64`, "
        "or listen on 127.0.0.1 (and tunnel, e.g. ssh -L)",
        server, host, port, token.size(), kMinRemoteTokenBytes, kTokenEnvironmentVariable));
  }
}

std::string AddressBlock(const std::string& peer) {
  in_addr v4{};
  if (inet_pton(AF_INET, peer.c_str(), &v4) == 1) {
    std::uint8_t b[4];
    std::memcpy(b, &v4, 4);
    return fmt::format("{}.{}.{}.0/24", b[0], b[1], b[2]);
  }
  in6_addr v6{};
  if (inet_pton(AF_INET6, peer.c_str(), &v6) == 1) {
    const std::uint8_t* b = v6.s6_addr;
    static constexpr std::uint8_t kMapped[12] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0xff, 0xff};
    if (std::memcmp(b, kMapped, 12) == 0) {
      return fmt::format("{}.{}.{}.0/24", b[12], b[13], b[14]);
    }
    in6_addr prefix{};
    std::memcpy(prefix.s6_addr, b, 8);
    char text[INET6_ADDRSTRLEN] = {};
    if (inet_ntop(AF_INET6, &prefix, text, sizeof(text)) != nullptr) {
      return std::string(text) + "/64";
    }
  }
  return peer;
}

AuthThrottle::Verdict AuthThrottle::Check(const std::string& peer, Clock::time_point now) const {
  if (IsLocked(peer, now)) return Verdict::kBlockLocked;
  if (IsRateLimited(now)) return Verdict::kRateLimited;
  return Verdict::kAllowed;
}

std::string AuthThrottle::RefusalText(Verdict verdict, const std::string& peer) {
  switch (verdict) {
    case Verdict::kBlockLocked:
      return fmt::format("too many wrong tokens from {} (address block {}): locked out for {} s "
                         "after the last one", peer, AddressBlock(peer), kLockout.count());
    case Verdict::kRateLimited:
      return fmt::format("auth rate limit: more than {} wrong tokens from all addresses "
                         "together; every opening is refused until the budget refills (one "
                         "per {} s); try again shortly", kGlobalBurst, kGlobalRefill.count());
    case Verdict::kAllowed:
      break;
  }
  return {};
}

bool AuthThrottle::IsLocked(const std::string& peer, Clock::time_point now) const {
  const auto it = blocks_.find(AddressBlock(peer));
  return it != blocks_.end() && now < it->second.locked_until;
}

double AuthThrottle::GlobalBudget(Clock::time_point now) const {
  if (!budget_started_) return kGlobalBurst;
  const double refilled = std::chrono::duration<double>(now - budget_time_).count() /
                          std::chrono::duration<double>(kGlobalRefill).count();
  return std::min<double>(kGlobalBurst, budget_ + std::max(0.0, refilled));
}

bool AuthThrottle::IsRateLimited(Clock::time_point now) const { return GlobalBudget(now) < 1.0; }

bool AuthThrottle::RecordFailure(const std::string& peer, Clock::time_point now) {
  ++failures_;
  budget_ = std::max(0.0, GlobalBudget(now) - 1.0);
  budget_time_ = now;
  budget_started_ = true;
  Prune(now);
  Entry& e = blocks_[AddressBlock(peer)];
  if (e.failures == 0 || now - e.first_failure > kFailureWindow) {
    e.failures = 0;
    e.first_failure = now;
  }
  ++e.failures;
  if (e.failures < kMaxFailures) return false;
  e.failures = 0;
  e.locked_until = now + kLockout;
  return true;
}

void AuthThrottle::RecordSuccess(const std::string& peer) { blocks_.erase(AddressBlock(peer)); }

void AuthThrottle::Prune(Clock::time_point now) {
  if (blocks_.size() < kMaxTracked) return;
  for (auto it = blocks_.begin(); it != blocks_.end();) {
    const bool stale = now >= it->second.locked_until &&
                       now - it->second.first_failure > kFailureWindow;
    it = stale ? blocks_.erase(it) : std::next(it);
  }
  // Still full (a flood of fresh blocks): forget entries (in block order) rather than grow
  // without bound; a forgotten block starts counting again (the global budget still holds).
  while (blocks_.size() >= kMaxTracked) blocks_.erase(blocks_.begin());
}

}  // namespace hybridtest::transfer
