#pragma once
// SettledReadingCheck: is a reading that a bench calls "settled" really the answer to the
// command just sent? One check for every transfer system that reports a settled move itself
// and cannot be watched while it moves: a Modbus controller (its ack) and a Python bench
// driver (its return). Both call the same object after every answered command.
//
// Per actuator k, with the command c, the measured position p, and the previous exchange's
// command c' and position p' since the last Reset(), all in the bench's length unit (the
// stop's value and limit in [m]):
//
//   1. stale acknowledgement:  |c − c'| > 2 settle_tolerance  and  p == p' (bit for bit)
//      A settled actuator is within settle_tolerance of its command, so after a command
//      that moved by more than two settling windows it cannot show the position it showed
//      before. A controller that acknowledges before it updates its data (or a driver that
//      returns a cached reading) shows exactly that. Limit "stale_acknowledgement"
//      (value |c − c'|, limit 2 settle_tolerance). Position sensors must resolve better
//      than two settling windows (1 µm counts against 0.1 mm: yes).
//   2. following error:  |c − p| ≤ following_error
//      Limit "following_error".
//
// A violation throws SafetyStop naming the actuator, both values in the bench's length unit
// and how to proceed; the caller has put its bench on hold (see `Source::after`).
//
// The limits default from the bench's settling tolerance (its in-position window), not from
// the command increment: a settled actuator meets them, and a 1.5 mm lie does not pass.
//   settle_tolerance  default kDefaultSettleTolerance (0.05 mm)
//   following_error   default min(kFollowingErrorPerSettleTolerance · settle_tolerance,
//                                 max_increment)  (0.2 mm with the defaults)
#include <cstddef>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace hybridtest::transfer {

inline constexpr double kDefaultSettleTolerance = 0.05e-3;  // Unit: [m].
// The default following error in settling windows: the window itself, the position sensor's
// noise and the drift between settling and sampling, with room to spare.
inline constexpr double kFollowingErrorPerSettleTolerance = 4.0;

// min(kFollowingErrorPerSettleTolerance · settle_tolerance, max_increment), in the unit of
// both arguments.
double DefaultFollowingError(double settle_tolerance, double max_increment);
// A length [m] in a bench unit of `metres_per_unit` [m], rounded to 12 significant digits so
// that a default reads as it was meant (0.05 mm, not 0.049999999999999996 mm).
double InBenchUnit(double metres, double metres_per_unit);

class SettledReadingCheck {
 public:
  // In the bench's length unit (Source::unit).
  struct Limits {
    double following_error = 0.0;   // largest |command − position|
    double settle_tolerance = 0.0;  // the bench's in-position window
  };
  // What the messages say about the bench. Lengths in messages are in `unit`.
  struct Source {
    std::string unit;                // the bench's length unit name ("mm", "m")
    double metres_per_unit = 1.0;
    // "The Modbus controller at H unit 1 (actuator 2) acknowledged command 1.5 mm (sequence
    // 3)": who answered which command, for actuator k.
    std::function<std::string(std::size_t)> answered;
    // What was read, for actuator k (may be empty): " (position … at input registers …)".
    std::function<std::string(std::size_t)> detail;
    std::string after;               // what the caller did: "the hold coil was set"
    std::string following_key;       // where the limit is set: "transfer.following_error"
    std::string settle_key;          // where the window is set: "transfer.settle_tolerance"
  };

  SettledReadingCheck() = default;
  // One entry per actuator. Throws ConfigError unless every value is positive and finite.
  explicit SettledReadingCheck(std::vector<Limits> limits);

  // Forgets the previous exchange (after Activate: the actuator may have been moved by hand).
  void Reset();
  // Checks one answered move of every actuator (commands and positions in the bench's length
  // unit, one per actuator). Throws
  // SafetyStop (limit "stale_acknowledgement" or "following_error") for the first actuator
  // that fails; remembers the exchange only if all pass.
  void Check(std::span<const double> commands, std::span<const double> positions,
             const Source& source);

  const std::vector<Limits>& limits() const { return limits_; }

 private:
  std::vector<Limits> limits_;
  std::vector<double> last_command_;   // bench length unit; empty: no previous exchange
  std::vector<double> last_position_;  // bench length unit
};

}  // namespace hybridtest::transfer
