#pragma once
// SourceBackoff: wrong tokens slow only the source that sends them. The monitor's actions
// (monitor_server.h) compare the token first, in constant time; a right token is served
// whatever came before, from that address or any other. Only a wrong one (or none) asks this
// table, keyed by the source (an IPv4 address; an IPv6 /64, which one host owns; an
// IPv4-mapped IPv6 address as its IPv4 address):
//
//   - the first kFreeFailures failed attempts of a source are answered at once (401/403);
//   - after that the source waits: kFirstWait, doubled at each further failure up to
//     kMaxWait; a failed attempt within its wait is answered 429 with the wait left
//     (Retry-After) and neither counted nor logged (a flood does not flood the log);
//   - a source quiet for kForget is forgotten; at most kMaxSources are remembered (the one
//     quiet for longest makes room), so the table's memory is bounded whatever the number
//     of addresses.
//
// No global budget: nothing one source sends changes what another is answered.
#include <chrono>
#include <cstddef>
#include <string>
#include <unordered_map>

namespace hybridtest::monitor {

class SourceBackoff {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr int kFreeFailures = 3;
  static constexpr std::chrono::milliseconds kFirstWait{1000};
  static constexpr std::chrono::milliseconds kMaxWait{60000};
  static constexpr std::chrono::seconds kForget{300};
  static constexpr std::size_t kMaxSources = 1024;

  // The key of `peer` ("127.0.0.5", "::ffff:10.0.0.1", "2001:db8::1").
  static std::string SourceOf(const std::string& peer);

  // How long `peer` must still wait before a failed attempt counts again (0 if it need not).
  Clock::duration Wait(const std::string& peer, Clock::time_point now) const;
  // A failed attempt of `peer` outside its wait; returns the wait it starts (0 for a free one).
  Clock::duration Failure(const std::string& peer, Clock::time_point now);
  // `peer` showed the right token: its failures are forgotten.
  void Success(const std::string& peer);

  std::size_t sources() const { return table_.size(); }

 private:
  struct Entry {
    int failures = 0;
    Clock::time_point last;       // the last counted failure
    Clock::time_point wait_until;
  };
  std::unordered_map<std::string, Entry> table_;
};

}  // namespace hybridtest::monitor
