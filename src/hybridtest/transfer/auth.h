#pragma once
// Authentication of the bench protocol's shared token (docs/protocol.md §3): where a token
// comes from, how it is compared and how failed attempts are throttled.
//
//  - A token is a secret: it is given by file (--token-file, a run config's `token_file:`) or by
//    the environment (HYBRIDTEST_BENCH_TOKEN), never on a command line (visible to every user in
//    /proc/PID/cmdline) and never in a run config (copied verbatim into the results).
//  - TokensEqual() takes a time that depends only on the lengths, not on where the first
//    differing byte is, so that timing does not reveal a prefix.
//  - AuthThrottle counts wrong tokens per peer address: after kMaxFailures wrong tokens within
//    kFailureWindow, that address is locked out for kLockout (every HELLO from it is refused
//    without looking at its token). Other addresses are not affected, so a guesser cannot lock
//    the real client out from another machine.
//  - CheckBindPolicy(): a server binds a loopback address freely, any other only with a token.
//    BenchServer (bench_server.h) and the OpenFresco server (openfresco/server.h) share it.
//
// The token proves the client knows the secret; the link itself is not encrypted (see
// docs/protocol.md for SSH tunnels off loopback).
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <string_view>

namespace hybridtest::transfer {

inline constexpr const char* kTokenEnvironmentVariable = "HYBRIDTEST_BENCH_TOKEN";
inline constexpr std::size_t kMaxTokenBytes = 1024;

// Constant-time (in the content) equality of two tokens.
bool TokensEqual(std::string_view a, std::string_view b) noexcept;

// The token in the file at `path`: its first line without trailing whitespace. Throws
// ConfigError naming `where` if the file cannot be read, is empty, or is longer than
// kMaxTokenBytes.
std::string ReadTokenFile(const std::string& path, const std::string& where);

// The token in HYBRIDTEST_BENCH_TOKEN, or empty.
std::string TokenFromEnvironment();

// The bind policy: returns if `host` is loopback or `token` is set; otherwise throws
// ConfigError naming `server` (e.g. "the bench"), host:port and the two ways out (a token, or
// 127.0.0.1 and a tunnel). Throws ConfigError too if `host` does not resolve.
void CheckBindPolicy(const std::string& host, std::uint16_t port, const std::string& token,
                     const std::string& server);

class AuthThrottle {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr int kMaxFailures = 5;
  static constexpr std::chrono::seconds kFailureWindow{60};
  static constexpr std::chrono::seconds kLockout{60};
  static constexpr std::size_t kMaxTracked = 4096;  // addresses remembered at once

  // True while `peer` is locked out.
  bool IsLocked(const std::string& peer, Clock::time_point now) const;
  // Records a wrong token from `peer`; returns true if this failure starts a lockout.
  bool RecordFailure(const std::string& peer, Clock::time_point now);
  // Forgets `peer`'s failures (after a correct token).
  void RecordSuccess(const std::string& peer);

 private:
  struct Entry {
    int failures = 0;
    Clock::time_point first_failure;
    Clock::time_point locked_until;
  };
  void Prune(Clock::time_point now);
  std::map<std::string, Entry> peers_;
};

}  // namespace hybridtest::transfer
