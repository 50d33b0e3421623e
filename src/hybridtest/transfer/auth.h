#pragma once
// Authentication of the bench protocol's shared token (docs/protocol.md §3): where a token
// comes from, how it is compared and how failed attempts are throttled.
//
//  - A token is a secret: it is given by file (--token-file, a run config's `token_file:`) or by
//    the environment (HYBRIDTEST_BENCH_TOKEN), never on a command line (visible to every user in
//    /proc/PID/cmdline) and never in a run config (copied verbatim into the results).
//  - TokensEqual() takes a time that depends only on the lengths, not on where the first
//    differing byte is, so that timing does not reveal a prefix.
//  - AuthThrottle counts wrong tokens per address block (IPv4 /24, IPv6 /64; an IPv4-mapped
//    IPv6 address counts as its IPv4 address), not per address, so that rotating source
//    addresses (127.0.0.x, a /64 of IPv6 addresses) does not multiply the guesses: after
//    kMaxFailures wrong tokens from one block within kFailureWindow, that block is locked out
//    for kLockout (every opening from it is refused without looking at its token). A
//    neighbour in the same block is locked out with the guesser; other blocks are not.
//  - On top of that, a global budget bounds the wrong tokens from all addresses together: a
//    bucket of kGlobalBurst failures that refills one failure per kGlobalRefill. While it is
//    empty, every opening, from anyone and with any token, is refused unread ("rate limit");
//    a guesser spread over many blocks gets at most about one guess per kGlobalRefill.
//    Under such an attack the real client is refused too: safety before availability.
//  - CheckBindPolicy(): a server binds a loopback address freely, any other only with a token
//    of at least kMinRemoteTokenBytes bytes that is not only whitespace. A token that is only
//    whitespace is refused on any address. BenchServer (bench_server.h) and the OpenFresco
//    server (openfresco/server.h) share it.
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
inline constexpr std::size_t kMinRemoteTokenBytes = 16;  // off-loopback binds

// Constant-time (in the content) equality of two tokens.
bool TokensEqual(std::string_view a, std::string_view b) noexcept;

// The token in the file at `path`: its first line without trailing whitespace. Throws
// ConfigError naming `where` if the file cannot be read, is empty, or is longer than
// kMaxTokenBytes.
std::string ReadTokenFile(const std::string& path, const std::string& where);

// The token in HYBRIDTEST_BENCH_TOKEN, or empty.
std::string TokenFromEnvironment();

// The bind policy: returns if `host` is loopback, or if `token` has at least
// kMinRemoteTokenBytes bytes and is not only whitespace; otherwise throws ConfigError naming
// `server` (e.g. "the bench"), host:port, what is wrong with the token and the two ways out (a
// long token, or 127.0.0.1 and a tunnel). A non-empty token of only whitespace is refused on
// loopback too. Throws ConfigError too if `host` does not resolve.
void CheckBindPolicy(const std::string& host, std::uint16_t port, const std::string& token,
                     const std::string& server);

// The address block a peer address belongs to, as text: "10.1.2.0/24" for IPv4 (and for
// IPv4-mapped IPv6 "::ffff:10.1.2.3"), "2001:db8:0:1::/64" for IPv6; the input unchanged if it
// is not a numeric address (e.g. "unknown").
std::string AddressBlock(const std::string& peer);

class AuthThrottle {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr int kMaxFailures = 5;               // per block within kFailureWindow
  static constexpr std::chrono::seconds kFailureWindow{60};
  static constexpr std::chrono::seconds kLockout{60};
  static constexpr int kGlobalBurst = 10;              // wrong tokens, all blocks together
  static constexpr std::chrono::seconds kGlobalRefill{1};  // one more allowed per this
  static constexpr std::size_t kMaxTracked = 4096;     // blocks remembered at once

  enum class Verdict {
    kAllowed,      // compare the token
    kBlockLocked,  // the peer's block is locked out
    kRateLimited,  // the global budget of wrong tokens is spent
  };
  // Whether an opening from `peer` may have its token compared at `now`.
  Verdict Check(const std::string& peer, Clock::time_point now) const;
  // Why an opening is refused unread, for the log and the client: names the block and the
  // wait (kBlockLocked) or the global budget (kRateLimited). Empty for kAllowed.
  static std::string RefusalText(Verdict verdict, const std::string& peer);
  // True while `peer`'s block is locked out.
  bool IsLocked(const std::string& peer, Clock::time_point now) const;
  // True while the global budget is spent.
  bool IsRateLimited(Clock::time_point now) const;
  // Records a wrong token from `peer` (its block, and the global budget); returns true if this
  // failure starts a lockout of the block.
  bool RecordFailure(const std::string& peer, Clock::time_point now);
  // Forgets the failures of `peer`'s block (after a correct token). The global budget is not
  // refunded.
  void RecordSuccess(const std::string& peer);

  long failures() const { return failures_; }  // lifetime count of RecordFailure()

 private:
  struct Entry {
    int failures = 0;
    Clock::time_point first_failure;
    Clock::time_point locked_until;
  };
  void Prune(Clock::time_point now);
  double GlobalBudget(Clock::time_point now) const;  // failures still allowed now
  std::map<std::string, Entry> blocks_;
  double budget_ = kGlobalBurst;       // at budget_time_
  Clock::time_point budget_time_{};
  bool budget_started_ = false;
  long failures_ = 0;
};

}  // namespace hybridtest::transfer
