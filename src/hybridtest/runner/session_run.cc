// See session.h: the one loop of every run (Session::Run) and the real-time setting the
// Session builds from its spec (decision 0016, issue 46).
#include <fmt/core.h>

#include "hybridtest/common/error.h"
#include "hybridtest/runner/delay_stability.h"
#include "hybridtest/runner/paced_loop.h"
#include "hybridtest/runner/real_time_setup.h"
#include "hybridtest/runner/session.h"

namespace hybridtest::runner {

void Session::Note(const std::string& message) const {
  if (options_.note) options_.note(message);
}

void Session::BuildPacer() {
  const io::RealTimeSpec& rt = spec_.real_time;
  if (!rt.enabled) {
    if (!rt.clock.empty()) {
      throw ConfigError(fmt::format("clock {}: this config has no `real_time:` block; the clock "
                                    "chooses the time of a real-time run only "
                                    "(docs/real-time.md)", rt.clock));
    }
    return;
  }
  if (options_.clock != nullptr) {
    clock_ = options_.clock;
  } else {
    own_clock_ = MakeClock(rt.clock);
    clock_ = own_clock_.get();
  }
  // Refuses a scheme or a transfer system that cannot run paced (nothing has moved).
  paced_loop_.reset(new PacedLoop(*this, *clock_));
  pacer_ = paced_loop_.get();
  // Before anything moves: the delay each physical slot can bear (delay_stability.h).
  const std::vector<SlotDelayMargin> margins = CheckDelayStability(*this);
  for (const SlotDelayMargin& g : margins) {
    Note(fmt::format("real time: {}{}", Describe(g),
                     g.unstable() ? (rt.force ? " — UNSTABLE, run forced" : " — UNSTABLE") : ""));
  }
  paced_loop_->SetStability(ToJson(margins));
  RefuseUnstable(*this, margins);
}

StepResult Session::Run() {
  StepResult r = initialized_ ? result_ : Initialize();
  if (r.status == SessionStatus::kWorking && pacer_ != nullptr && !paced_) {
    if (!clock_->is_virtual()) {
      for (const std::string& note : PrepareRealTimeProcess(spec_.real_time)) {
        paced_loop_->AddSetupNote(note);
        Note("real time: " + note);
      }
    }
    // Every transfer system runs paced from here; one that cannot refuses before any tick.
    try {
      pacer_->Start();
    } catch (const std::exception&) {
      for (auto& s : subs_) s->Hold();
      // Every queued event delivered before the caller's observers may go.
      if (queue_ != nullptr) queue_->Drain();
      throw;
    }
    paced_ = true;
  }
  while (r.status == SessionStatus::kWorking) {
    bool after_hold = false;
    if (between_steps_) {
      const long holds = holds_;
      r = between_steps_(*this);
      if (r.status != SessionStatus::kWorking) break;
      after_hold = holds_ != holds;
    }
    if (pacer_ != nullptr) pacer_->BeforeStep(after_hold);
    r = Step();
    if (pacer_ != nullptr) pacer_->AfterStep(r);
  }
  return r;
}

}  // namespace hybridtest::runner
