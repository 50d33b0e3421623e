// AdsServer's PLC program (ads_server.h): one cycle after every write, and the move of the
// bench when a new command sequence arrives.
#include <fmt/core.h>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/ads/ads_server.h"

namespace hybridtest::transfer::ads {

void AdsServer::HoldBench(const std::string& why) {
  if (bench_active_) bench_.Hold();
  bench_active_ = false;
  Log("hold: " + why);
}

std::uint32_t AdsServer::Cycle(bool& close) {
  if (options_.program == PlcProgram::kPHybrid) return 0;  // it runs on its own cycle
  const AdsProfile& p = options_.profile;
  const bool enable = image_.Bool(kEnable);
  const bool hold = image_.Bool(kHold);
  bool fault = image_.Bool(kFault);
  if (enable && !last_enable_) {
    if (fault) {
      fault = false;
      image_.SetBool(kFault, false);
      Log(fmt::format("fault cleared by a rising {}", p.symbols[kEnable]));
    }
  }
  const bool was_enabled = image_.Bool(kEnabled);
  const bool enabled = enable && !fault;
  if (hold && !last_hold_) HoldBench(p.symbols[kHold] + " set by a client");
  if (was_enabled && !enabled) HoldBench(p.symbols[kEnable] + " cleared: the drive is disabled");
  last_enable_ = enable;
  last_hold_ = hold;
  image_.SetBool(kEnabled, enabled);
  image_.SetBool(kHolding, hold || fault);
  // A new command: the sequence changed.
  const std::uint32_t sequence = image_.Udint(kSequence);
  if (sequence == last_sequence_) return 0;
  if (sequence == image_.Udint(kAck)) {  // the release of a hold drops a pending command
    last_sequence_ = sequence;
    return 0;
  }
  const std::uint32_t previous = last_sequence_;
  last_sequence_ = sequence;
  const long n = ++commands_received_;
  if (!enabled || hold) {
    Log(fmt::format("command {} ({} = {}) ignored: the PLC is {}", n, p.symbols[kSequence],
                    sequence, !enabled ? "not enabled" : "holding"));
    return 0;
  }
  if (silenced_) return 0;
  for (auto it = options_.faults.begin(); it != options_.faults.end(); ++it) {
    if (it->command != n) continue;
    const AdsFault::Kind kind = it->kind;
    options_.faults.erase(it);  // a test fault fires once
    switch (kind) {
      case AdsFault::Kind::kSilence:
        silenced_ = true;
        Log(fmt::format("TEST FAULT silence@{}: no acknowledgement from now on", n));
        return 0;
      case AdsFault::Kind::kClose:
        close = true;
        Log(fmt::format("TEST FAULT close@{}: the connection is closed", n));
        return 0;
      case AdsFault::Kind::kAdsError:
        last_sequence_ = previous;
        image_.SetUdint(kSequence, previous);
        Log(fmt::format("TEST FAULT ads_error@{}: the write is answered with ADS error {}", n,
                        AdsErrorName(kErrBusy)));
        return kErrBusy;
      case AdsFault::Kind::kFault:
        image_.SetBool(kFault, true);
        image_.SetBool(kHolding, true);
        image_.SetBool(kEnabled, false);
        HoldBench(fmt::format("TEST FAULT fault@{}: {} set instead of the ack", n, p.symbols[kFault]));
        return 0;
      case AdsFault::Kind::kHolding:
        Execute(sequence, n);
        image_.SetBool(kHold, true);
        image_.SetBool(kHolding, true);
        last_hold_ = true;
        HoldBench(fmt::format("TEST FAULT holding@{}: an operator holds after the ack", n));
        return 0;
    }
  }
  Execute(sequence, n);
  return 0;
}

bool AdsServer::Move(long n) {
  const std::vector<double> commands = image_.Reals(kCommand);
  std::vector<GatedMove> moves;
  try {
    gate_.MoveBench(bench_, commands, {n, 0}, moves, [&] {
      if (!bench_active_) {
        bench_.Activate();
        bench_active_ = true;
      }
    });
  } catch (const std::exception& e) {
    // A refused command or a bench that failed: the PLC faults and holds.
    image_.SetBool(kFault, true);
    image_.SetBool(kHolding, true);
    image_.SetBool(kEnabled, false);
    HoldBench(fmt::format("command {} refused, {} set: {}", n, options_.profile.symbols[kFault],
                          e.what()));
    return false;
  }
  actual_.position.clear();
  actual_.force.clear();
  for (const GatedMove& m : moves) {
    actual_.position.push_back(m.raw.position);
    actual_.force.push_back(m.raw.force);
  }
  return true;
}

void AdsServer::Execute(std::uint32_t sequence, long n) {
  if (!Move(n)) return;
  image_.SetReals(kPosition, actual_.position);
  image_.SetReals(kForce, actual_.force);
  image_.SetUdint(kAck, sequence);
}

}  // namespace hybridtest::transfer::ads
