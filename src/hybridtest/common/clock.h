#pragma once
// Clock: the time a paced (real-time) run lives on (decision 0015). Two kinds, one interface:
//
//   MonotonicClock  the wall clock: CLOCK_MONOTONIC, seconds since the clock was made;
//                   WaitUntil sleeps to an ABSOLUTE deadline (clock_nanosleep, TIMER_ABSTIME),
//                   so a late tick never shifts the later ones (no drift); it wakes up
//                   kSpinBeforeDeadline early and spins the rest (a sleep is late by the
//                   thread's timer slack, a spin is not).
//   VirtualClock    simulated time: WaitUntil jumps to the deadline at once, no sleeping;
//                   every run is bit-reproducible (tests, plan, a dry run the day before).
//
// An emulated plant advances its state to Now() on every command, so the same code runs in
// virtual time and paced on the wall clock. Unit of every time here: [s].
#include <string>

namespace hybridtest {

class Clock {
 public:
  virtual ~Clock() = default;
  // Time since the clock's origin. Unit: [s].
  virtual double Now() const = 0;
  // Returns at time t (at once if t has passed). Unit: [s].
  virtual void WaitUntil(double t) = 0;
  // True for simulated time (no sleeping).
  virtual bool is_virtual() const = 0;
  virtual std::string name() const = 0;
};

// How long before a deadline MonotonicClock::WaitUntil stops sleeping and spins. Unit: [s].
inline constexpr double kSpinBeforeDeadline = 200e-6;

class MonotonicClock final : public Clock {
 public:
  MonotonicClock();
  double Now() const override;
  void WaitUntil(double t) override;
  bool is_virtual() const override { return false; }
  std::string name() const override { return "wall"; }

 private:
  long origin_s_ = 0;    // CLOCK_MONOTONIC at construction: seconds
  long origin_ns_ = 0;   // and nanoseconds
};

class VirtualClock final : public Clock {
 public:
  explicit VirtualClock(double start = 0.0) : now_(start) {}
  double Now() const override { return now_; }
  void WaitUntil(double t) override {
    if (t > now_) now_ = t;
  }
  bool is_virtual() const override { return true; }
  std::string name() const override { return "virtual"; }

 private:
  double now_;
};

}  // namespace hybridtest
