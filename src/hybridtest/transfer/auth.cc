// See auth.h.
#include "hybridtest/transfer/auth.h"

#include <fmt/core.h>

#include <cstdlib>
#include <fstream>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/socket.h"

namespace hybridtest::transfer {

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
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw ConfigError(fmt::format("{} = '{}': cannot read the token file; check the path and "
                                  "its permissions", where, path));
  }
  std::string token(kMaxTokenBytes + 2, '\0');
  in.read(token.data(), static_cast<std::streamsize>(token.size()));
  token.resize(static_cast<std::size_t>(in.gcount()));
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

void CheckBindPolicy(const std::string& host, std::uint16_t port, const std::string& token,
                     const std::string& server) {
  if (!token.empty() || IsLoopbackHost(host)) return;
  throw ConfigError(fmt::format(
      "refusing to serve {} on {}:{} without a token: a non-loopback address lets anyone on the "
      "network move the actuator; set a shared token (--token-file or {}) or listen on "
      "127.0.0.1 (and tunnel, e.g. ssh -L)",
      server, host, port, kTokenEnvironmentVariable));
}

bool AuthThrottle::IsLocked(const std::string& peer, Clock::time_point now) const {
  const auto it = peers_.find(peer);
  return it != peers_.end() && now < it->second.locked_until;
}

bool AuthThrottle::RecordFailure(const std::string& peer, Clock::time_point now) {
  Prune(now);
  Entry& e = peers_[peer];
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

void AuthThrottle::RecordSuccess(const std::string& peer) { peers_.erase(peer); }

void AuthThrottle::Prune(Clock::time_point now) {
  if (peers_.size() < kMaxTracked) return;
  for (auto it = peers_.begin(); it != peers_.end();) {
    const bool stale = now >= it->second.locked_until &&
                       now - it->second.first_failure > kFailureWindow;
    it = stale ? peers_.erase(it) : std::next(it);
  }
  // Still full (a flood of fresh addresses): forget entries (in address order) rather than
  // grow without bound; a forgotten address starts counting again.
  while (peers_.size() >= kMaxTracked) peers_.erase(peers_.begin());
}

}  // namespace hybridtest::transfer
