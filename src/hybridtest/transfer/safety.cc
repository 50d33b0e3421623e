#include "hybridtest/transfer/safety.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

namespace hybridtest::transfer {
namespace {

// Secant stiffness needs two positions at least this far apart. Unit: [m].
constexpr double kMinSecantBaseline = 1e-6;

std::string FormatStopMessage(const std::string& limit, double value, double limit_value,
                              long step, int stage, const std::string& detail) {
  return fmt::format("safety stop: {} violated at step {} stage {}: value {:.6g}, limit {:.6g}. {}",
                     limit, step, stage, value, limit_value, detail);
}

// |slope| of the least-squares line of force over position through the answered, finite
// exchanges of `history` [N/m]; NaN when their positions span less than kMinSecantBaseline.
// Through two exchanges it is their secant. Over a window a paced loop's per-tick scatter
// (a late tick, the specimen's inertia and damping force over a step of a few µm) averages
// out, where the secant of the last two exchanges jumped by orders of magnitude.
double WindowStiffness(const std::vector<ExchangeRecord>& history) {
  double n = 0.0, mx = 0.0, mf = 0.0;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const ExchangeRecord& r : history) {
    if (!r.answered || !std::isfinite(r.position) || !std::isfinite(r.force)) continue;
    n += 1.0;
    mx += r.position;
    mf += r.force;
    lo = std::min(lo, r.position);
    hi = std::max(hi, r.position);
  }
  if (n < 2.0 || hi - lo < kMinSecantBaseline) return std::numeric_limits<double>::quiet_NaN();
  mx /= n;
  mf /= n;
  double sxx = 0.0, sxf = 0.0;
  for (const ExchangeRecord& r : history) {
    if (!r.answered || !std::isfinite(r.position) || !std::isfinite(r.force)) continue;
    sxx += (r.position - mx) * (r.position - mx);
    sxf += (r.position - mx) * (r.force - mf);
  }
  return std::abs(sxf / sxx);
}

void RequireFinite(const char* name, double value) {
  if (!std::isfinite(value)) {
    throw ConfigError(fmt::format("safety.{} = {}: expected a finite number", name, value));
  }
}

}  // namespace

SafetyStop::SafetyStop(std::string limit, double value, double limit_value, long step, int stage,
                       std::vector<ExchangeRecord> history, const std::string& detail)
    : Error(FormatStopMessage(limit, value, limit_value, step, stage, detail)),
      limit_(std::move(limit)),
      value_(value),
      limit_value_(limit_value),
      step_(step),
      stage_(stage),
      history_(std::move(history)) {}

SafetyMonitor::SafetyMonitor(SafetyLimits limits, std::size_t history_length)
    : limits_(limits), history_length_(history_length) {
  history_.reserve(history_length_ + 1);
  RequireFinite("stroke_min", limits_.stroke_min);
  RequireFinite("stroke_max", limits_.stroke_max);
  if (!(limits_.stroke_min < limits_.stroke_max)) {
    throw ConfigError(fmt::format(
        "safety.stroke_min = {} m is not below safety.stroke_max = {} m: expected min < max; "
        "swap or correct them",
        limits_.stroke_min, limits_.stroke_max));
  }
  if (!(std::isfinite(limits_.max_increment) && limits_.max_increment > 0.0)) {
    throw ConfigError(fmt::format(
        "safety.max_increment = {} m: expected a positive length per stage", limits_.max_increment));
  }
  if (!(std::isfinite(limits_.force_hard) && limits_.force_hard > 0.0)) {
    throw ConfigError(fmt::format(
        "safety.force_hard = {} N: expected a positive force (at most the load-cell capacity)",
        limits_.force_hard));
  }
  if (!(std::isfinite(limits_.force_soft) && limits_.force_soft > 0.0 &&
        limits_.force_soft <= limits_.force_hard)) {
    throw ConfigError(fmt::format(
        "safety.force_soft = {} N: expected a positive force not above safety.force_hard = {} N",
        limits_.force_soft, limits_.force_hard));
  }
  if (!(std::isfinite(limits_.timeout) && limits_.timeout > 0.0)) {
    throw ConfigError(fmt::format(
        "safety.timeout = {} s: expected a positive time in seconds", limits_.timeout));
  }
  if (history_length_ == 0) {
    throw ConfigError("safety history length = 0: expected at least 1 exchange to keep");
  }
}

void SafetyMonitor::SetStartPosition(double position) {
  if (!std::isfinite(position) || position < limits_.stroke_min ||
      position > limits_.stroke_max) {
    throw ConfigError(fmt::format(
        "start position {} m: expected a finite position inside the stroke [{}, {}] m; move the "
        "actuator into the stroke or correct the limits",
        position, limits_.stroke_min, limits_.stroke_max));
  }
  last_safe_command_ = position;
  has_safe_command_ = true;
  from_start_ = true;
}

void SafetyMonitor::SetInitialStiffness(double stiffness) {
  RequireFinite("initial_stiffness", stiffness);
  initial_stiffness_ = stiffness;
}

double SafetyMonitor::PredictForce(double command) const {
  if (!has_measurement_) return std::numeric_limits<double>::quiet_NaN();
  const double k = has_secant_ ? secant_stiffness_ : initial_stiffness_;
  return last_force_ + k * (command - last_position_);
}

void SafetyMonitor::Stop(const std::string& limit, double value, double limit_value, long step,
                         int stage, const std::string& what) const {
  const std::string hold =
      has_safe_command_
          ? fmt::format("The actuator holds at the last safe command {:.6g} m.", last_safe_command_)
          : std::string("No command was accepted yet; the actuator holds where it is.");
  throw SafetyStop(limit, value, limit_value, step, stage, history(),
                   fmt::format("{} {}", what, hold));
}

void SafetyMonitor::CheckCommand(double command, long step, int stage) {
  CheckCommand(command, step, stage, PredictForce(command), {});
}

void SafetyMonitor::CheckCommand(double command, long step, int stage, double predicted,
                                 std::string_view basis_text) {
  VetCommand(command, step, stage, predicted, basis_text);
  AcceptCommand(command, step, stage);
}

void SafetyMonitor::VetCommand(double command, long step, int stage, double predicted,
                               std::string_view basis_text) const {
  // 1. Finite.
  if (!std::isfinite(command)) {
    Stop("command_finite", command, 0.0, step, stage,
         "The command is NaN or infinite: the model produced an invalid displacement. To "
         "proceed: check the model state and the time step (an explicit scheme may be unstable), "
         "then continue from the last committed step with `hybridtest resume RUN.csv` (the "
         "run's journal).");
  }
  // 2. Inside the stroke.
  if (command < limits_.stroke_min || command > limits_.stroke_max) {
    const bool low = command < limits_.stroke_min;
    Stop(low ? "stroke_min" : "stroke_max", command,
         low ? limits_.stroke_min : limits_.stroke_max, step, stage,
         fmt::format("The command {:.6g} m is outside the stroke [{:.6g}, {:.6g}] m and was not "
                     "sent. To proceed: check p0 and the expected amplitude; widen "
                     "safety.stroke_min/stroke_max only if the actuator and specimen allow it.",
                     command, limits_.stroke_min, limits_.stroke_max));
  }
  // 3. Increment from the last accepted command.
  if (has_safe_command_) {
    const double increment = std::abs(command - last_safe_command_);
    if (increment > limits_.max_increment && from_start_) {
      // The first command: the model starts at rest at d = 0, so a jump here is not a step
      // size but a start position that is not where the runner thinks (p0, units).
      Stop("max_increment", increment, limits_.max_increment, step, stage,
           fmt::format("The first command {:.6g} m is {:.6g} m from the start position {:.6g} m "
                       "and was not sent. A jump at the first command is not a step-size "
                       "problem: the runner's p0 (setup.p0, where the specimen carries no force) "
                       "and where the actuator stands disagree, or a unit slipped (a p0 in mm "
                       "typed into a field in m, or the bench's p0_mm given in m). To proceed: "
                       "compare setup.p0 [m] with the bench's p0 (p0_mm / 1000) and the units "
                       "of both; do not raise safety.max_increment or shrink the time step for "
                       "this.",
                       command, increment, last_safe_command_));
    }
    if (increment > limits_.max_increment) {
      Stop("max_increment", increment, limits_.max_increment, step, stage,
           fmt::format("The command {:.6g} m jumps {:.6g} m from the last accepted command and "
                       "was not sent. To proceed: reduce the time step, or raise "
                       "safety.max_increment if such jumps are expected.",
                       command, increment));
    }
  }
  // 4. Predicted force inside force_soft.
  if (std::isfinite(predicted) && std::abs(predicted) > limits_.force_soft) {
    const std::string basis =
        basis_text.empty()
            ? fmt::format("last force {:.6g} N, stiffness estimate {:.6g} N/m", last_force_,
                          has_secant_ ? secant_stiffness_ : initial_stiffness_)
            : std::string(basis_text);
    Stop("force_soft", std::abs(predicted), limits_.force_soft, step, stage,
         fmt::format("The command {:.6g} m would produce about {:.6g} N ({}) and was not sent. "
                     "To proceed: check the specimen and p0; raise safety.force_soft (at most "
                     "force_hard) only if the specimen is rated for it.",
                     command, predicted, basis));
  }
}

void SafetyMonitor::AcceptCommand(double command, long step, int stage) {
  last_safe_command_ = command;
  has_safe_command_ = true;
  from_start_ = false;
  Remember({step, stage, command, 0.0, 0.0, false});
}

void SafetyMonitor::CheckMeasurement(double command, double position, double force, long step,
                                     int stage) {
  // Record the exchange first: the stop report must show the offending measurement.
  if (!history_.empty() && !history_.back().answered && history_.back().step == step &&
      history_.back().stage == stage && history_.back().command == command) {
    history_.back().position = position;
    history_.back().force = force;
    history_.back().answered = true;
  } else {
    Remember({step, stage, command, position, force, true});
  }
  if (!std::isfinite(position) || !std::isfinite(force)) {
    const bool bad_force = !std::isfinite(force);
    Stop(bad_force ? "force_finite" : "position_finite", bad_force ? force : position, 0.0, step,
         stage,
         fmt::format("The measurement (position {} m, force {} N) is not finite: a sensor, "
                     "cable or amplifier failed. To proceed: check the load cell and encoder "
                     "wiring and readings at rest, then continue from the last committed step with "
                     "`hybridtest resume RUN.csv` (the run's journal).",
                     position, force));
  }
  if (std::abs(force) > limits_.force_hard) {
    Stop("force_hard", std::abs(force), limits_.force_hard, step, stage,
         fmt::format("The measured force {:.6g} N at position {:.6g} m exceeds the hard limit. "
                     "To proceed: inspect the specimen for damage before anything else; then "
                     "check p0 and the load-cell calibration. Do not raise force_hard above the "
                     "load-cell or actuator rating.",
                     force, position));
  }
  // Update the stiffness estimate from the answered exchanges of the history.
  if (const double k = WindowStiffness(history_); std::isfinite(k)) {
    secant_stiffness_ = k;
    has_secant_ = true;
  }
  last_position_ = position;
  last_force_ = force;
  has_measurement_ = true;
}

double SafetyMonitor::last_safe_command() const { return last_safe_command_; }
bool SafetyMonitor::has_safe_command() const { return has_safe_command_; }

std::vector<ExchangeRecord> SafetyMonitor::history() const {
  return {history_.begin(), history_.end()};
}

void SafetyMonitor::Remember(const ExchangeRecord& record) {
  history_.push_back(record);
  if (history_.size() > history_length_) {
    history_.erase(history_.begin(), history_.end() - static_cast<long>(history_length_));
  }
}

}  // namespace hybridtest::transfer
