// See safety_gate.h.
#include "hybridtest/transfer/safety_gate.h"

#include <fmt/core.h>

#include <cmath>
#include <limits>

namespace hybridtest::transfer {

SafetyGate::SafetyGate(const std::vector<SafetyLimits>& limits) {
  if (limits.empty()) throw ConfigError("safety: a specimen needs the limits of at least one actuator");
  for (const auto& l : limits) monitors_.emplace_back(l);
}

void SafetyGate::SetStiffness(const Eigen::MatrixXd& k) {
  if (k.rows() != size() || k.cols() != size() || !k.allFinite()) {
    throw ConfigError(fmt::format("safety: a {} × {} stiffness for the force prediction of {} "
                                  "actuators; expected a finite {} × {} matrix in N/m", k.rows(),
                                  k.cols(), size(), size(), size()));
  }
  stiffness_ = k;
}

void UseCoupledStiffness(SafetyGate& gate, const Eigen::MatrixXd& k) {
  gate.SetStiffness(k);
  for (int a = 0; a < gate.size(); ++a) gate.monitor(a).SetInitialStiffness(k(a, a));
}

void PredictCoupledForces(const std::vector<SafetyMonitor>& monitors,
                          const Eigen::MatrixXd& stiffness, std::span<const double> commands_m,
                          CommandScratch& scratch) {
  const auto n = static_cast<Eigen::Index>(monitors.size());
  Eigen::VectorXd& f = scratch.predicted;
  f.setConstant(n, std::numeric_limits<double>::quiet_NaN());
  if (static_cast<Eigen::Index>(commands_m.size()) != n || stiffness.rows() != n ||
      stiffness.cols() != n) {
    return;
  }
  scratch.move.resize(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const auto& m = monitors[static_cast<std::size_t>(k)];
    if (!m.has_measurement()) return;
    scratch.move(k) = commands_m[static_cast<std::size_t>(k)] - m.last_position();
  }
  f.noalias() = stiffness * scratch.move;
  for (Eigen::Index k = 0; k < n; ++k) f(k) += monitors[static_cast<std::size_t>(k)].last_force();
}

void CheckCommands(std::vector<SafetyMonitor>& monitors, const Eigen::MatrixXd* stiffness,
                   std::span<const double> commands_m, long step, int stage,
                   CommandScratch& scratch) {
  const std::size_t n = monitors.size();
  // One actuator, each monitor on its own: a refused command leaves its monitor untouched.
  if (n == 1 && stiffness == nullptr) {
    monitors[0].CheckCommand(commands_m[0], step, stage);
    return;
  }
  VetCommands(monitors, stiffness, commands_m, step, stage, scratch);
  for (std::size_t k = 0; k < n; ++k) monitors[k].AcceptCommand(commands_m[k], step, stage);
}

void VetCommands(const std::vector<SafetyMonitor>& monitors, const Eigen::MatrixXd* stiffness,
                 std::span<const double> commands_m, long step, int stage,
                 CommandScratch& scratch) {
  const std::size_t n = monitors.size();
  if (stiffness != nullptr) {
    PredictCoupledForces(monitors, *stiffness, commands_m, scratch);
  } else {
    scratch.predicted.setConstant(static_cast<Eigen::Index>(n),
                                  std::numeric_limits<double>::quiet_NaN());
  }
  // Every command vetted before any monitor learns one: a refused vector changes none.
  for (std::size_t k = 0; k < n; ++k) {
    const double f = scratch.predicted(static_cast<Eigen::Index>(k));
    if (std::isfinite(f)) {
      monitors[k].VetCommand(commands_m[k], step, stage, f,
                             "predicted with the coupled stiffness in actuator coordinates: "
                             "f_last + K_a (a − x_last), every actuator's move counted");
    } else {
      monitors[k].VetCommand(commands_m[k], step, stage, monitors[k].PredictForce(commands_m[k]),
                             {});
    }
  }
}

void SafetyGate::Vet(std::span<const double> commands_m, MoveLabel label) {
  if (commands_m.size() != monitors_.size()) {
    throw Error(fmt::format("SafetyGate: {} commands proposed for {} actuators", commands_m.size(),
                            monitors_.size()));
  }
  VetCommands(monitors_, stiffness_ ? &*stiffness_ : nullptr, commands_m, label.step,
              label.stage, scratch_);
}

Eigen::VectorXd SafetyGate::PredictForces(const std::vector<double>& commands_m) const {
  if (!stiffness_) {
    return Eigen::VectorXd::Constant(size(), std::numeric_limits<double>::quiet_NaN());
  }
  CommandScratch scratch;
  PredictCoupledForces(monitors_, *stiffness_, commands_m, scratch);
  return scratch.predicted;
}

void SafetyGate::Move(TransferSystem& transfer, const std::vector<double>& commands_m,
                      MoveLabel label, const std::vector<double>& load_cell_zero,
                      std::vector<GatedMove>& out, const std::function<void()>& before_execute) {
  const BenchUnits units = transfer.bench_units();
  bench_commands_.resize(commands_m.size());
  for (std::size_t k = 0; k < commands_m.size(); ++k) {
    bench_commands_[k] = commands_m[k] / units.metres_per_length_unit;
  }
  Execute(transfer, commands_m, label, load_cell_zero, out, before_execute);
}

void SafetyGate::MoveBench(TransferSystem& transfer, std::span<const double> commands_bench,
                           MoveLabel label, std::vector<GatedMove>& out,
                           const std::function<void()>& before_execute) {
  const BenchUnits units = transfer.bench_units();
  bench_commands_.assign(commands_bench.begin(), commands_bench.end());
  commands_m_.resize(commands_bench.size());
  for (std::size_t k = 0; k < commands_m_.size(); ++k) {
    commands_m_[k] = commands_bench[k] * units.metres_per_length_unit;
  }
  zeros_.assign(commands_m_.size(), 0.0);
  Execute(transfer, commands_m_, label, zeros_, out, before_execute);
}

void SafetyGate::Execute(TransferSystem& transfer, std::span<const double> commands_m,
                         MoveLabel label, std::span<const double> load_cell_zero,
                         std::vector<GatedMove>& out,
                         const std::function<void()>& before_execute) {
  const std::size_t n = monitors_.size();
  if (commands_m.size() != n || load_cell_zero.size() != n ||
      transfer.num_actuators() != static_cast<int>(n)) {
    throw Error(fmt::format("SafetyGate: {} monitors, {} commands, {} load-cell zeros and a "
                            "transfer system of {} actuators: expected one of each per actuator",
                            n, commands_m.size(), load_cell_zero.size(),
                            transfer.num_actuators()));
  }
  out.resize(n);
  for (auto& o : out) o.executed = false;
  // 1. Every command before any actuator moves.
  for (std::size_t k = 0; k < n; ++k) out[k].command = commands_m[k];
  CheckCommands(monitors_, stiffness_ ? &*stiffness_ : nullptr, commands_m, label.step,
                label.stage, scratch_);
  if (before_execute) before_execute();
  // 2. All commands at once.
  const BenchUnits units = transfer.bench_units();
  measured_.resize(n);
  transfer.Execute(bench_commands_, measured_);
  // 3. Every measurement.
  for (std::size_t k = 0; k < n; ++k) {
    const Measurement& m = measured_[k];
    out[k].raw = m;
    out[k].position = m.position * units.metres_per_length_unit;
    out[k].force = m.force * units.newtons_per_force_unit - load_cell_zero[k];
    out[k].lab_time = m.lab_time;
    out[k].executed = true;
  }
  for (std::size_t k = 0; k < n; ++k) {
    monitors_[k].CheckMeasurement(commands_m[k], out[k].position, out[k].force, label.step,
                                  label.stage);
  }
}

}  // namespace hybridtest::transfer
