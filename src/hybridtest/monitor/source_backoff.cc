// See source_backoff.h.
#include "hybridtest/monitor/source_backoff.h"

#include <arpa/inet.h>

#include <algorithm>
#include <cstring>

namespace hybridtest::monitor {

std::string SourceBackoff::SourceOf(const std::string& peer) {
  in6_addr v6{};
  if (::inet_pton(AF_INET6, peer.c_str(), &v6) == 1) {
    if (IN6_IS_ADDR_V4MAPPED(&v6)) {
      char text[INET_ADDRSTRLEN] = {};
      ::inet_ntop(AF_INET, &v6.s6_addr[12], text, sizeof text);
      return text;
    }
    std::memset(&v6.s6_addr[8], 0, 8);  // the /64
    char text[INET6_ADDRSTRLEN] = {};
    ::inet_ntop(AF_INET6, &v6, text, sizeof text);
    return std::string(text) + "/64";
  }
  return peer;
}

SourceBackoff::Clock::duration SourceBackoff::Wait(const std::string& peer,
                                                   Clock::time_point now) const {
  const auto it = table_.find(SourceOf(peer));
  if (it == table_.end() || it->second.wait_until <= now) return Clock::duration::zero();
  return it->second.wait_until - now;
}

SourceBackoff::Clock::duration SourceBackoff::Failure(const std::string& peer,
                                                      Clock::time_point now) {
  const std::string key = SourceOf(peer);
  auto it = table_.find(key);
  if (it != table_.end() && now - it->second.last > kForget) {
    table_.erase(it);
    it = table_.end();
  }
  if (it == table_.end()) {
    if (table_.size() >= kMaxSources) {
      // Forget the sources quiet for kForget; if none, the one quiet for longest.
      std::erase_if(table_, [&](const auto& e) { return now - e.second.last > kForget; });
      if (table_.size() >= kMaxSources) {
        table_.erase(std::min_element(table_.begin(), table_.end(), [](const auto& a,
                                                                       const auto& b) {
          return a.second.last < b.second.last;
        }));
      }
    }
    it = table_.emplace(key, Entry{}).first;
  }
  Entry& e = it->second;
  ++e.failures;
  e.last = now;
  if (e.failures <= kFreeFailures) return Clock::duration::zero();
  const int doublings = std::min(e.failures - kFreeFailures - 1, 16);
  const auto wait = std::min<Clock::duration>(kFirstWait * (1L << doublings), kMaxWait);
  e.wait_until = now + wait;
  return wait;
}

void SourceBackoff::Success(const std::string& peer) { table_.erase(SourceOf(peer)); }

}  // namespace hybridtest::monitor
