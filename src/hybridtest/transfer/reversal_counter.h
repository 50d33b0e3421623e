#pragma once
// ReversalCounter: how often a signal changes direction, with a deadband. A reversal is
// counted when the signal, having moved one way, retreats from its extreme by more than the
// deadband; the first direction it takes is not a reversal. The emulated bench counts the
// reversals of the true specimen force within one move (move, settle and sampling window): a
// move that approaches its target without overshoot has none, and on a hysteretic specimen
// each one is a small unloading–reloading cycle that the numerical model never asked for.
#include <cmath>

namespace hybridtest::transfer {

class ReversalCounter {
 public:
  // deadband: the smallest retreat that counts, in the signal's unit (> 0).
  explicit ReversalCounter(double deadband) : deadband_(deadband) {}

  // Starts a new record at `value` (count 0, no direction yet).
  void Reset(double value) {
    extreme_ = value;
    direction_ = 0;
    count_ = 0;
  }

  void Add(double value) {
    if (!std::isfinite(value)) return;
    if (direction_ == 0) {
      // The first move beyond the deadband sets the direction.
      if (std::abs(value - extreme_) > deadband_) {
        direction_ = value > extreme_ ? 1 : -1;
        extreme_ = value;
      }
      return;
    }
    const double along = direction_ > 0 ? value - extreme_ : extreme_ - value;
    if (along > 0.0) {
      extreme_ = value;
    } else if (-along > deadband_) {
      ++count_;
      direction_ = -direction_;
      extreme_ = value;
    }
  }

  long count() const { return count_; }

 private:
  double deadband_;
  double extreme_ = 0.0;
  int direction_ = 0;
  long count_ = 0;
};

}  // namespace hybridtest::transfer
