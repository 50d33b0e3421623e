// AdsServer's P_Hybrid (ads_server.h, PlcProgram::kPHybrid): docs/ads.md's Structured Text,
// one statement group per step, run every cycle_time. The emulated bench stands in for the
// axes: MoveAbsolute is the gated move (the safety gate refusing is DriveFault), the bench
// arrives within the cycle, so InPosition() AND Settled() hold the cycle after the move.
#include <fmt/core.h>

#include "hybridtest/transfer/ads/ads_server.h"

namespace hybridtest::transfer::ads {

void AdsServer::ProgramCycle() {
  const AdsProfile& p = options_.profile;
  PHybrid& v = program_;
  const auto now = std::chrono::steady_clock::now();

  // 1. Fault and enable. A rising bEnable resets a fault.
  const bool enable = image_.Bool(kEnable);
  if (enable && !v.last_enable && image_.Bool(kFault)) {
    image_.SetBool(kFault, false);
    Log(fmt::format("fault cleared by a rising {}", p.symbols[kEnable]));
  }
  v.last_enable = enable;
  // DriveFault(): set by Move() when the safety gate refuses a command; DrivesReady(): always.
  image_.SetBool(kEnabled, enable && !image_.Bool(kFault));

  // 2. The watchdog: nHeartbeat unchanged for PT while enabled and not held sets bHold.
  const std::uint32_t beat = image_.Udint(kHeartbeat);
  const bool in = image_.Bool(kEnabled) && !image_.Bool(kHold) && beat == v.last_heartbeat;
  if (in && !v.watchdog_in) v.watchdog_since = now;  // TON: IN rising starts the timer
  v.watchdog_in = in;
  v.last_heartbeat = beat;
  if (in && std::chrono::duration<double>(now - v.watchdog_since).count() >= options_.watchdog) {
    image_.SetBool(kHold, true);
    Log(fmt::format("watchdog: {} unchanged ({}) for {} s while enabled: {} := TRUE",
                    p.symbols[kHeartbeat], beat, options_.watchdog, p.symbols[kHold]));
  }
  // OperatorHold(): never in the emulator.
  const bool holding = image_.Bool(kHold) || image_.Bool(kFault);
  image_.SetBool(kHolding, holding);

  // 3. Live values, every cycle.
  image_.SetReals(kPosition, actual_.position);
  image_.SetReals(kForce, actual_.force);

  // 4. The state machine: IDLE, MOVING, HELD.
  if (holding || !image_.Bool(kEnabled)) {
    if (!v.held) HoldBench(v.moving ? "holding: the move is abandoned" : "holding");
    v.held = true;
    v.moving = false;
  } else if (!v.moving && image_.Udint(kSequence) != image_.Udint(kAck)) {
    v.taken = image_.Udint(kSequence);
    v.held = false;
    v.moving = Move(++commands_received_);  // false: refused, bFault set (HELD next cycle)
    v.held = !v.moving;
  } else if (v.moving) {  // InPosition() AND Settled(): step 3's values are the sample
    image_.SetUdint(kAck, v.taken);
    v.moving = false;
  }
}

}  // namespace hybridtest::transfer::ads
