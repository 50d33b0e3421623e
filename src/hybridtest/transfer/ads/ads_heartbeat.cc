// AdsTransfer's heartbeat (ads_transfer.h; docs/ads.md "The watchdog"): the counter the PLC's
// watchdog watches. Kept apart from the exchange so that it is written the same way wherever
// hybridtest waits on the PLC.
#include <fmt/core.h>

#include "hybridtest/transfer/ads/ads_transfer.h"

namespace hybridtest::transfer::ads {

std::vector<std::uint8_t> AdsTransfer::NextHeartbeat() {
  ++heartbeat_;  // modulo 2^32, as a UDINT
  last_beat_ = std::chrono::steady_clock::now();
  return EncodeUdint(heartbeat_);
}

void AdsTransfer::BeatIfDue() {
  if (handles_.size() != kNumRoles) return;  // not connected: ReadOutputs says so
  const double since =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - last_beat_).count();
  if (since < kHeartbeatPeriod) return;
  link_.Write(kGroupValueByHandle, handles_[kHeartbeat], NextHeartbeat(),
              options_.response_timeout,
              "the heartbeat " + options_.profile.symbols[kHeartbeat]);  // AdsError names a refusal
}

void AdsTransfer::BeatWhileWaiting() {
  try {
    BeatIfDue();
  } catch (const AdsError& e) {
    HoldAndFail(fmt::format("{}; {} was set", e.what(), options_.profile.symbols[kHold]));
  }
}

}  // namespace hybridtest::transfer::ads
