#include "hybridtest/transfer/emulated_bench.h"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/actuator.h"
#include "hybridtest/transfer/lab_clock.h"
#include "hybridtest/transfer/load_cell.h"
#include "hybridtest/transfer/reversal_counter.h"

namespace hybridtest::transfer {
namespace {

std::string DescribeLag(const ServoLag& lag) {
  switch (lag.type) {
    case ServoLag::Type::kNone:
      return "no lag";
    case ServoLag::Type::kFirstOrder:
      return fmt::format("first-order lag {:g} ms", lag.time_constant * 1e3);
    case ServoLag::Type::kSecondOrder:
      return fmt::format("second-order lag {:g} Hz, zeta={:g}", lag.natural_frequency,
                         lag.damping_ratio);
  }
  return "";
}

}  // namespace

EmulatedBench::EmulatedBench(const EmulatedBenchConfig& config)
    : config_(config), safety_((ValidateEmulatedBenchConfig(config), config.safety)) {
  specimen_ = config_.specimen->Clone();
  actuator_ = std::make_unique<Actuator>(config_);
  load_cell_ = std::make_unique<LoadCell>(config_.noise_std, config_.resolution, config_.offset,
                                          config_.seed);
  clock_ = std::make_unique<LabClock>(config_.realtime);
  // The specimen starts deformed if the actuator does not start at p0.
  specimen_->Trial(config_.initial_position - config_.p0);
  specimen_->Commit();
}

EmulatedBench::~EmulatedBench() = default;

void EmulatedBench::Activate() {
  if (state_ == State::kConfigured) {
    safety_.SetStartPosition(config_.initial_position);
    safety_.SetInitialStiffness(specimen_->initial_stiffness());
    clock_->Start();
  }
  state_ = State::kActive;
}

Measurement EmulatedBench::Execute(double command) {
  if (state_ != State::kActive) {
    throw TransferError(fmt::format(
        "emulated bench: Execute({} {}) while the bench is {}: expected an active bench; call "
        "Activate() first (also to resume after a hold)",
        command, config_.units.length_name,
        state_ == State::kHolding ? "holding" : "not active"));
  }
  const long index = command_count_++;  // 0-based, the safety monitor's step
  // 1-based, the fault injector's convention; 0 (no fault) for a command whose faults fired
  // before a resume.
  const long fault_index = index + 1 > faults_fired_through_ ? index + 1 : 0;
  const double target = command * config_.units.metres_per_length_unit;  // [m]
  const double dt = actuator_->step();

  // 0. The bench's own safety check: a refused command never moves the actuator.
  try {
    safety_.CheckCommand(target, index, 0);
  } catch (...) {
    Hold();
    throw;
  }
  if (HasFault(config_.faults, FaultKind::kSilence, fault_index)) {
    // TEST FACILITY: the bench does not answer; the caller waits out the timeout.
    clock_->Advance(config_.safety.timeout);
    clock_->Pace();
    Hold();
    throw TransferError(fmt::format(
        "emulated bench: no measurement for command {} ({} {}) within the timeout of {} s "
        "(injected fault 'silence'); the bench holds",
        fault_index, command, config_.units.length_name, config_.safety.timeout));
  }
  clock_->Advance(config_.overhead);

  // Advances the actuator one internal step, deforms the specimen along the path and returns
  // the true specimen force [N] (counting its reversals); trips the drive beyond its capacity.
  ReversalCounter reversals(kForceReversalDeadband * config_.capacity);
  bool first_step = true;
  auto advance = [&]() {
    actuator_->Step(target);
    const double force = specimen_->Trial(actuator_->position() - config_.p0);
    specimen_->Commit();
    if (first_step) {
      reversals.Reset(force);
      first_step = false;
    } else {
      reversals.Add(force);
    }
    if (!(std::abs(force) <= config_.capacity)) {
      Hold();
      throw SafetyStop("actuator_capacity", std::abs(force), config_.capacity, index, 0,
                       safety_.history(),
                       fmt::format("The drive tripped at position {:.6g} m: the specimen force "
                                   "exceeds the actuator capacity; it holds there. To proceed: "
                                   "inspect the specimen and check p0.",
                                   actuator_->position()));
    }
    return force;
  };

  // 1–2. Move and settle: |target − p| < tolerance continuously for the dwell time.
  double phase_time = 0.0;
  double dwell = 0.0;
  for (;;) {
    advance();
    phase_time += dt;
    const bool inside = actuator_->reference_arrived(target) &&
                        std::abs(target - actuator_->position()) < config_.settle_tolerance;
    dwell = inside ? dwell + dt : 0.0;
    if (inside && dwell >= config_.settle_dwell - 0.5 * dt) break;
    if (phase_time > config_.safety.timeout) {
      clock_->Advance(phase_time);
      Hold();
      throw TransferError(fmt::format(
          "emulated bench: the actuator did not settle within {} m of {} m in {} s (position "
          "{} m); check the lag parameters, settling.tolerance_mm and safety.timeout_s",
          config_.settle_tolerance, target, config_.safety.timeout, actuator_->position()));
    }
  }

  // 3. Sample: average over the window (deviations from the first sample, so that identical
  // samples average exactly to themselves).
  const long samples = std::max(1L, std::lround(config_.sampling_window / dt));
  double first_position = 0.0, first_force = 0.0, sum_dp = 0.0, sum_df = 0.0;
  for (long i = 0; i < samples; ++i) {
    const double reading = load_cell_->Sample(advance());
    if (i == 0) {
      first_position = actuator_->position();
      first_force = reading;
    }
    sum_dp += actuator_->position() - first_position;
    sum_df += reading - first_force;
  }
  const double n = static_cast<double>(samples);
  const double position = first_position + sum_dp / n;  // [m]
  const double force = first_force + sum_df / n;        // [N]
  clock_->Advance(phase_time + n * dt);

  // 4. The bench's own measurement check.
  try {
    safety_.CheckMeasurement(target, position, force, index, 0);
  } catch (...) {
    Hold();
    throw;
  }
  // Position relative to the command, so that an exact arrival reports the command exactly.
  Measurement measurement{command + (position - target) / config_.units.metres_per_length_unit,
                          force / config_.units.newtons_per_force_unit, clock_->lab_time(),
                          reversals.count()};
  ApplyMeasurementFaults(config_.faults, fault_index, config_.units, measurement);
  clock_->Pace();
  return measurement;
}

void EmulatedBench::Hold() noexcept {
  // The emulated actuator only moves inside Execute: holding means refusing to move until
  // Activate() resumes. It stays where it is (the last safe command, or where the drive
  // tripped).
  if (state_ == State::kActive) state_ = State::kHolding;
}

void EmulatedBench::Deactivate() {
  Hold();
  state_ = State::kDeactivated;
}

std::string EmulatedBench::Describe() const {
  return fmt::format(
      "emulated bench ({}; p0={:g} mm; {}/{}; {}, delay {:g} ms, {:g} mm/s; noise {:g} N, "
      "resolution {:g} N; {}{})",
      specimen_->Describe(), config_.p0 * 1e3, config_.units.length_name,
      config_.units.force_name, DescribeLag(config_.lag), config_.delay * 1e3,
      config_.velocity_limit * 1e3, config_.noise_std, config_.resolution,
      config_.realtime ? "realtime" : "accelerated",
      config_.faults.empty() ? "" : fmt::format(", {} injected faults", config_.faults.size()));
}

double EmulatedBench::lab_time() const { return clock_->lab_time(); }
double EmulatedBench::actuator_position() const { return actuator_->position(); }

std::unique_ptr<EmulatedBench> MakeEmulatedBench(const EmulatedBenchConfig& config) {
  return std::make_unique<EmulatedBench>(config);
}

}  // namespace hybridtest::transfer
