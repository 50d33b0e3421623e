// See emulated_bench.h.
#include "hybridtest/transfer/emulated_bench.h"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/actuator.h"
#include "hybridtest/transfer/lab_clock.h"
#include "hybridtest/transfer/load_cell.h"
#include "hybridtest/transfer/reversal_counter.h"
#include "hybridtest/transfer/safety_gate.h"

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

// "3 mm" for one command, "[3, 4] mm" for several.
std::string Commands(std::span<const double> commands, const std::string& unit) {
  if (commands.size() == 1) return fmt::format("{} {}", commands[0], unit);
  std::string list;
  for (const double c : commands) list += fmt::format("{}{}", list.empty() ? "" : ", ", c);
  return fmt::format("[{}] {}", list, unit);
}

const EmulatedBenchSpec& Checked(const EmulatedBenchSpec& spec) {
  const auto n = spec.actuators.size();
  const auto rows = static_cast<Eigen::Index>(n);
  if (n == 0 || spec.stiffness.rows() != rows || spec.stiffness.cols() != rows ||
      !spec.stiffness.allFinite()) {
    throw ConfigError(fmt::format("emulated bench: {} actuators and a {} × {} stiffness: "
                                  "expected a finite n × n matrix (n ≥ 1)", n,
                                  spec.stiffness.rows(), spec.stiffness.cols()));
  }
  const auto& first = spec.actuators[0];
  for (std::size_t k = 0; k < n; ++k) {
    const auto& a = spec.actuators[k];
    ValidateEmulatedBenchConfig(a);
    if (a.internal_step != first.internal_step ||
        a.units.metres_per_length_unit != first.units.metres_per_length_unit ||
        a.units.newtons_per_force_unit != first.units.newtons_per_force_unit) {
      throw ConfigError(fmt::format("emulated bench: actuator {} has another internal step or "
                                    "other wire units than actuator 1; give them once for all",
                                    k + 1));
    }
  }
  return spec;
}

}  // namespace

EmulatedBench::EmulatedBench(const EmulatedBenchSpec& spec) : spec_(Checked(spec)) {
  const auto n = spec_.actuators.size();
  for (const auto& a : spec_.actuators) {
    safety_.emplace_back(a.safety);
    actuators_.push_back(std::make_unique<Actuator>(a));
    load_cells_.push_back(std::make_unique<LoadCell>(a.noise_std, a.resolution, a.offset, a.seed));
  }
  clock_ = std::make_unique<LabClock>(spec_.actuators[0].realtime);
  specimen_ = spec_.specimen ? spec_.specimen->Clone()
                             : std::make_unique<constitutive::LinearCoupledLaw>(spec_.stiffness);
  if (specimen_->num_axes() != static_cast<int>(n)) {
    throw ConfigError(fmt::format("emulated bench: a specimen of {} axes on {} actuators",
                                  specimen_->num_axes(), n));
  }
  deformation_.resize(n);
  target_.resize(n);
  force_.resize(static_cast<Eigen::Index>(n));
  // The specimen starts deformed if an actuator does not start at its p0.
  Deform();
}

EmulatedBench::EmulatedBench(const EmulatedBenchConfig& config)
    : EmulatedBench(OneActuatorSpec((ValidateEmulatedBenchConfig(config), config))) {}

EmulatedBench::~EmulatedBench() = default;

void EmulatedBench::Activate() {
  if (state_ == State::kConfigured) {
    for (std::size_t k = 0; k < safety_.size(); ++k) {
      safety_[k].SetStartPosition(spec_.actuators[k].initial_position);
      // Each monitor's own prediction starts from the specimen's diagonal stiffness (the
      // `actuators:` form only where it is positive).
      const auto i = static_cast<Eigen::Index>(k);
      const double kkk = spec_.stiffness(i, i);
      if (kkk > 0.0 || !spec_.coupled_safety) safety_[k].SetInitialStiffness(kkk);
    }
    clock_->Start();
  }
  state_ = State::kActive;
}

const Eigen::VectorXd& EmulatedBench::Deform() {
  for (std::size_t k = 0; k < deformation_.size(); ++k) {
    deformation_[k] = actuators_[k]->position() - spec_.actuators[k].p0;
  }
  specimen_->Trial(deformation_, std::span<double>(force_.data(), deformation_.size()));
  specimen_->Commit();
  return force_;
}

Measurement EmulatedBench::Execute(double command) {
  if (num_actuators() != 1) {
    throw TransferError(fmt::format("emulated bench: one command for {} actuators; a "
                                    "substructure with `setup: transform` sends one per actuator",
                                    num_actuators()));
  }
  Measurement m;
  Execute(std::span<const double>(&command, 1), std::span<Measurement>(&m, 1));
  return m;
}

void EmulatedBench::Execute(std::span<const double> commands, std::span<Measurement> out) {
  const auto n = static_cast<std::size_t>(num_actuators());
  const EmulatedBenchConfig& first = spec_.actuators[0];
  const BenchUnits& units = first.units;
  if (commands.size() != n || out.size() != n) {
    throw TransferError(fmt::format("emulated bench: {} commands and {} measurements for {} "
                                    "actuators", commands.size(), out.size(), n));
  }
  if (state_ != State::kActive) {
    throw TransferError(fmt::format(
        "emulated bench: Execute({}) while the bench is {}: expected an active bench; call "
        "Activate() first (also to resume after a hold)", Commands(commands, units.length_name),
        state_ == State::kHolding ? "holding" : "not active"));
  }
  const long index = command_count_++;  // 0-based, the safety monitors' step
  // 1-based, the fault injector's convention; 0 (no fault) for a command whose faults fired
  // before a resume.
  const long fault_index = index + 1 > faults_fired_through_ ? index + 1 : 0;
  for (std::size_t k = 0; k < n; ++k) target_[k] = commands[k] * units.metres_per_length_unit;
  const double dt = first.internal_step;

  // 0. The bench's own safety check of every command: a refused command moves no actuator.
  try {
    CheckCommands(safety_, spec_.coupled_safety ? &spec_.stiffness : nullptr, target_, index, 0);
  } catch (...) {
    Hold();
    throw;
  }
  if (HasFault(first.faults, FaultKind::kSilence, fault_index)) {
    // TEST FACILITY: the bench does not answer; the caller waits out the timeout.
    clock_->Advance(first.safety.timeout);
    clock_->Pace();
    Hold();
    throw TransferError(fmt::format(
        "emulated bench: no measurement for command {} ({}) within the timeout of {} s "
        "(injected fault 'silence'); the bench holds",
        fault_index, Commands(commands, units.length_name), first.safety.timeout));
  }
  clock_->Advance(first.overhead);

  // Advances every actuator one internal step, deforms the specimen along the path and returns
  // the true specimen forces [N] (counting their reversals); trips a drive beyond its capacity.
  std::vector<ReversalCounter> reversals;
  reversals.reserve(n);
  for (const auto& a : spec_.actuators) reversals.emplace_back(kForceReversalDeadband * a.capacity);
  bool first_step = true;
  auto advance = [&]() -> const Eigen::VectorXd& {
    for (std::size_t k = 0; k < n; ++k) actuators_[k]->Step(target_[k]);
    const Eigen::VectorXd& force = Deform();
    for (std::size_t k = 0; k < n; ++k) {
      const double f = force(static_cast<Eigen::Index>(k));
      if (first_step) {
        reversals[k].Reset(f);
      } else {
        reversals[k].Add(f);
      }
    }
    first_step = false;
    for (std::size_t k = 0; k < n; ++k) {
      const double f = std::abs(force(static_cast<Eigen::Index>(k)));
      const double capacity = spec_.actuators[k].capacity;
      if (!(f <= capacity)) {
        Hold();
        throw SafetyStop(
            "actuator_capacity", f, capacity, index, 0, safety_[k].history(),
            n == 1 ? fmt::format("The drive tripped at position {:.6g} m: the specimen force "
                                 "exceeds the actuator capacity; it holds there. To proceed: "
                                 "inspect the specimen and check p0.",
                                 actuators_[k]->position())
                   : fmt::format("The drive of actuator {} tripped at position {:.6g} m: the "
                                 "specimen force exceeds its capacity; every actuator holds. To "
                                 "proceed: inspect the specimen and check p0.",
                                 k + 1, actuators_[k]->position()));
      }
    }
    return force;
  };

  // 1–2. Move together and settle: |target − p| < tolerance continuously for the dwell time,
  // every actuator.
  std::vector<double> dwell(n, 0.0);
  double phase_time = 0.0;
  for (;;) {
    advance();
    phase_time += dt;
    bool all = true;
    for (std::size_t k = 0; k < n; ++k) {
      const auto& a = spec_.actuators[k];
      const bool inside = actuators_[k]->reference_arrived(target_[k]) &&
                          std::abs(target_[k] - actuators_[k]->position()) < a.settle_tolerance;
      dwell[k] = inside ? dwell[k] + dt : 0.0;
      all = all && inside && dwell[k] >= a.settle_dwell - 0.5 * dt;
    }
    if (all) break;
    if (phase_time > first.safety.timeout) {
      clock_->Advance(phase_time);
      Hold();
      if (n == 1) {
        throw TransferError(fmt::format(
            "emulated bench: the actuator did not settle within {} m of {} m in {} s (position "
            "{} m); check the lag parameters, settling.tolerance_mm and safety.timeout_s",
            first.settle_tolerance, target_[0], first.safety.timeout, actuators_[0]->position()));
      }
      std::string positions;
      for (std::size_t k = 0; k < n; ++k) {
        positions += fmt::format("{}actuator {} at {} m for {} m", k == 0 ? "" : ", ", k + 1,
                                 actuators_[k]->position(), target_[k]);
      }
      throw TransferError(fmt::format(
          "emulated bench: the actuators did not all settle in {} s ({}); check the lag "
          "parameters, settling.tolerance_mm and safety.timeout_s", phase_time, positions));
    }
  }

  // 3. Sample every load cell over the window (deviations from the first sample, so that
  // identical samples average exactly to themselves).
  const long samples = std::max(1L, std::lround(first.sampling_window / dt));
  std::vector<double> p_first(n, 0.0), f_first(n, 0.0), sum_dp(n, 0.0), sum_df(n, 0.0);
  for (long i = 0; i < samples; ++i) {
    const Eigen::VectorXd& force = advance();
    for (std::size_t k = 0; k < n; ++k) {
      const double reading = load_cells_[k]->Sample(force(static_cast<Eigen::Index>(k)));
      if (i == 0) {
        p_first[k] = actuators_[k]->position();
        f_first[k] = reading;
      }
      sum_dp[k] += actuators_[k]->position() - p_first[k];
      sum_df[k] += reading - f_first[k];
    }
  }
  const double count = static_cast<double>(samples);
  clock_->Advance(phase_time + count * dt);

  // 4. The bench's own measurement checks.
  for (std::size_t k = 0; k < n; ++k) {
    const double position = p_first[k] + sum_dp[k] / count;  // [m]
    const double force = f_first[k] + sum_df[k] / count;     // [N]
    try {
      safety_[k].CheckMeasurement(target_[k], position, force, index, 0);
    } catch (...) {
      Hold();
      throw;
    }
    // Position relative to the command, so that an exact arrival reports the command exactly.
    out[k] = Measurement{commands[k] + (position - target_[k]) / units.metres_per_length_unit,
                         force / units.newtons_per_force_unit, clock_->lab_time(),
                         reversals[k].count()};
    ApplyMeasurementFaults(spec_.actuators[k].faults, fault_index, units, out[k]);
  }
  clock_->Pace();
}

void EmulatedBench::Hold() noexcept {
  // The emulated actuators only move inside Execute: holding means refusing to move until
  // Activate() resumes. They stay where they are (the last safe commands, or where a drive
  // tripped).
  if (state_ == State::kActive) state_ = State::kHolding;
}

void EmulatedBench::Deactivate() {
  Hold();
  state_ = State::kDeactivated;
}

std::string EmulatedBench::Describe() const {
  const EmulatedBenchConfig& first = spec_.actuators[0];
  if (num_actuators() == 1) {
    return fmt::format(
        "emulated bench ({}; p0={:g} mm; {}/{}; {}, delay {:g} ms, {:g} mm/s; noise {:g} N, "
        "resolution {:g} N; {}{})",
        specimen_->Describe(), first.p0 * 1e3, first.units.length_name, first.units.force_name,
        DescribeLag(first.lag), first.delay * 1e3, first.velocity_limit * 1e3, first.noise_std,
        first.resolution, first.realtime ? "realtime" : "accelerated",
        first.faults.empty() ? "" : fmt::format(", {} injected faults", first.faults.size()));
  }
  std::string p0;
  for (const auto& a : spec_.actuators) {
    p0 += fmt::format("{}{:g}", p0.empty() ? "" : ", ", a.p0 * 1e3);
  }
  return fmt::format("emulated bench with {} actuators ({}; p0 = [{}] mm; {}/{}; {})",
                     num_actuators(), specimen_->Describe(), p0, first.units.length_name,
                     first.units.force_name, first.realtime ? "realtime" : "accelerated");
}

double EmulatedBench::lab_time() const { return clock_->lab_time(); }
double EmulatedBench::actuator_position(int k) const {
  return actuators_[static_cast<std::size_t>(k)]->position();
}

std::unique_ptr<EmulatedBench> MakeEmulatedBench(const EmulatedBenchSpec& spec) {
  return std::make_unique<EmulatedBench>(spec);
}

std::unique_ptr<EmulatedBench> MakeEmulatedBench(const EmulatedBenchConfig& config) {
  return std::make_unique<EmulatedBench>(config);
}

}  // namespace hybridtest::transfer
