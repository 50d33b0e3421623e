// See multi_actuator_substructure.h.
#include "hybridtest/substructures/multi_actuator_substructure.h"

#include <Eigen/Dense>
#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "hybridtest/common/error.h"

namespace hybridtest::substructures {

MultiActuatorSubstructure::MultiActuatorSubstructure(
    std::string name, std::unique_ptr<transfer::TransferSystem> transfer, LinearSetup setup,
    std::vector<transfer::SafetyLimits> limits)
    : MultiActuatorSubstructure(std::move(name), std::move(transfer),
                                std::make_unique<LinearActuatorSetup>(std::move(setup)),
                                std::move(limits)) {}

MultiActuatorSubstructure::MultiActuatorSubstructure(
    std::string name, std::unique_ptr<transfer::TransferSystem> transfer,
    std::unique_ptr<ActuatorSetup> setup, std::vector<transfer::SafetyLimits> limits)
    : name_(std::move(name)), transfer_(std::move(transfer)), setup_(std::move(setup)),
      gate_(limits) {
  if (!transfer_) throw Error("MultiActuatorSubstructure '" + name_ + "': no transfer system");
  if (!setup_) throw Error("MultiActuatorSubstructure '" + name_ + "': no setup");
  const int n = setup_->num_actuators();
  if (gate_.size() != n) {
    throw ConfigError(fmt::format("{}: the setup has {} actuators and {} sets of safety limits "
                                  "were given", name_, n, gate_.size()));
  }
  for (int k = 0; k < n; ++k) gate_.monitor(k).SetStartPosition(setup_->p0()(k));
  last_.resize(static_cast<std::size_t>(n));
  commands_.resize(static_cast<std::size_t>(n));
  zeros_.assign(setup_->load_cell_zero().data(), setup_->load_cell_zero().data() + n);
  f_.resize(n);
}

void MultiActuatorSubstructure::SetSlotLimits(SlotLimits limits) {
  const auto m = static_cast<Eigen::Index>(num_slots());
  auto check = [&](const Eigen::VectorXd& v, const char* key, const char* unit) {
    if (v.size() != m || !(v.array() > 0.0).all() || v.hasNaN()) {
      throw ConfigError(fmt::format("{}: safety.slots.{} has {} values: expected one positive "
                                    "limit in {} per slot ({})", name_, key, v.size(), unit, m));
    }
  };
  if (limits.max_displacement.size() == 0) {
    limits.max_displacement = Eigen::VectorXd::Constant(m, std::numeric_limits<double>::infinity());
  }
  if (limits.max_force.size() == 0) {
    limits.max_force = Eigen::VectorXd::Constant(m, std::numeric_limits<double>::infinity());
  }
  check(limits.max_displacement, "max_displacement", "m");
  check(limits.max_force, "max_force", "N");
  if (limits.names.size() != static_cast<std::size_t>(m)) {
    limits.names.clear();
    for (Eigen::Index i = 0; i < m; ++i) limits.names.push_back(fmt::format("{}", i + 1));
  }
  slot_limits_ = std::move(limits);
}

void MultiActuatorSubstructure::CheckSlotDisplacements(std::span<const double> d,
                                                       const TrialContext& ctx) {
  if (!slot_limits_) return;
  for (std::size_t i = 0; i < d.size(); ++i) {
    const double limit = slot_limits_->max_displacement(static_cast<Eigen::Index>(i));
    if (std::abs(d[i]) <= limit) continue;  // NaN falls through: refused
    Hold();
    throw transfer::SafetyStop(
        "slot_max_displacement", d[i], limit, ctx.step, ctx.stage, gate_.monitor(0).history(),
        fmt::format("{}: slot {} displacement {} m is beyond its safety.slots.max_displacement "
                    "{} m (step {}, stage {}, t = {} s); refused before any actuator moved, "
                    "every actuator holds", name_, slot_limits_->names[i], d[i], limit, ctx.step,
                    ctx.stage, ctx.t));
  }
}

void MultiActuatorSubstructure::CheckSlotForces(std::span<const double> r,
                                                const TrialContext& ctx) {
  if (!slot_limits_) return;
  for (std::size_t i = 0; i < r.size(); ++i) {
    const double limit = slot_limits_->max_force(static_cast<Eigen::Index>(i));
    if (std::abs(r[i]) <= limit) continue;
    Hold();
    throw transfer::SafetyStop(
        "slot_max_force", r[i], limit, ctx.step, ctx.stage, gate_.monitor(0).history(),
        fmt::format("{}: slot {} restoring force {} N is beyond its safety.slots.max_force {} N "
                    "(step {}, stage {}, t = {} s); every actuator holds", name_,
                    slot_limits_->names[i], r[i], limit, ctx.step, ctx.stage, ctx.t));
  }
}

MultiActuatorSubstructure::~MultiActuatorSubstructure() {
  if (active_) Hold();
}

void MultiActuatorSubstructure::Activate() {
  transfer_->Activate();
  held_ = false;
  active_ = true;
  // A remote bench says how many actuators it has once connected.
  if (transfer_->num_actuators() != num_actuators()) {
    Hold();
    throw ConfigError(fmt::format("{}: the setup's transform has {} rows (actuators), the "
                                  "transfer system ({}) moves {}: give one row of T and one p0 "
                                  "per actuator", name_, num_actuators(), transfer_->Describe(),
                                  transfer_->num_actuators()));
  }
}

void MultiActuatorSubstructure::MoveAll(const std::vector<double>& commands,
                                        transfer::MoveLabel label) {
  held_ = false;
  auto record = [&] {
    if (moves_.empty() || !moves_[0].executed) return;
    ++evaluations_;
    for (std::size_t k = 0; k < last_.size(); ++k) {
      last_[k] = {commands[k], moves_[k].position, moves_[k].force, moves_[k].lab_time,
                  moves_[k].raw.force_reversals};
    }
  };
  try {
    gate_.Move(*transfer_, commands, label, zeros_, moves_);
  } catch (...) {
    record();
    Hold();
    throw;
  }
  record();
}

double MultiActuatorSubstructure::Trial(double displacement, const TrialContext& context) {
  if (num_slots() != 1) {
    throw Error(fmt::format("{}: a scalar trial of a substructure of {} slots; call TrialSlots",
                            name_, num_slots()));
  }
  double r = 0.0;
  TrialSlots({&displacement, 1}, {&r, 1}, context);
  return r;
}

void MultiActuatorSubstructure::TrialSlots(std::span<const double> d, std::span<double> r,
                                           const TrialContext& ctx) {
  const Eigen::Map<const Eigen::VectorXd> dv(d.data(), static_cast<Eigen::Index>(d.size()));
  CheckSlotDisplacements(d, ctx);
  try {
    setup_->CalcCommands(dv, Eigen::Map<Eigen::VectorXd>(commands_.data(), num_actuators()));
  } catch (const Error& e) {
    Hold();
    throw Error(fmt::format("{}: {} (step {}, stage {}, t = {} s; every actuator holds)", name_,
                            e.what(), ctx.step, ctx.stage, ctx.t));
  }
  try {
    MoveAll(commands_, {ctx.step, ctx.stage});
  } catch (const TransferError& e) {
    throw TransferError(fmt::format("{}: {} (step {}, stage {}, t = {} s; every actuator holds)",
                                    name_, e.what(), ctx.step, ctx.stage, ctx.t));
  }
  for (int k = 0; k < f_.size(); ++k) f_(k) = last_[static_cast<std::size_t>(k)].force;
  setup_->CalcSlotForces(dv, f_, Eigen::Map<Eigen::VectorXd>(r.data(),
                                                             static_cast<Eigen::Index>(r.size())));
  CheckSlotForces(r, ctx);
}

void MultiActuatorSubstructure::Hold() noexcept {
  if (held_) return;
  held_ = true;
  transfer_->Hold();
}

void MultiActuatorSubstructure::Deactivate() {
  if (!active_) return;
  active_ = false;
  transfer_->Deactivate();
}

std::string MultiActuatorSubstructure::Describe() const {
  return fmt::format("physical ({}; {} slots, {} actuators, {}): {}", name_, num_slots(),
                     num_actuators(), setup_->Describe(), transfer_->Describe());
}

std::optional<double> MultiActuatorSubstructure::initial_stiffness() const {
  if (k0_ && k0_->rows() == 1) return (*k0_)(0, 0);
  return std::nullopt;
}

void MultiActuatorSubstructure::SetInitialStiffness(const Eigen::MatrixXd& k0) {
  if (k0.rows() != num_slots() || k0.cols() != num_slots() || !k0.allFinite()) {
    throw ConfigError(fmt::format("{}: initial stiffness of {} × {}: expected a finite {} × {} "
                                  "matrix in N/m", name_, k0.rows(), k0.cols(), num_slots(),
                                  num_slots()));
  }
  k0_ = k0;
  // The gate predicts every actuator's force with the whole matrix: K_a = T⁺ᵀ K0 T⁺, with
  // T⁺ = (TᵀT)⁻¹Tᵀ (T⁻ᵀ K0 T⁻¹ for a square T), T = T0 = J(0).
  const Eigen::MatrixXd& t = setup_->linearisation();
  const Eigen::MatrixXd pinv = (t.transpose() * t).ldlt().solve(t.transpose());  // m × n
  gate_.SetStiffness(pinv.transpose() * k0 * pinv);
}

double MultiActuatorSubstructure::max_displacement_increment() const {
  double inc = std::numeric_limits<double>::infinity();
  for (int k = 0; k < num_actuators(); ++k) {
    const double row = setup_->CommandStepBound(k);
    if (row > 0.0) inc = std::min(inc, gate_.monitor(k).limits().max_increment / row);
  }
  return inc;
}

MultiActuatorSubstructure::StiffnessMeasurement MultiActuatorSubstructure::MeasureInitialStiffness(
    double amplitude) {
  if (!(amplitude > 0.0) || !std::isfinite(amplitude)) {
    throw ConfigError(fmt::format("{}: stiffness ramp amplitude {} m: expected a positive length",
                                  name_, amplitude));
  }
  const int n = num_actuators();
  StiffnessMeasurement out;
  out.amplitude = amplitude;
  for (int j = 0; j < n; ++j) {
    const double step_limit = 0.5 * gate_.monitor(j).limits().max_increment;
    const int steps = std::max(4, static_cast<int>(std::ceil(amplitude / step_limit)));
    for (int k = 1; k <= 2 * steps; ++k) {
      const int level = k <= steps ? k : 2 * steps - k;
      Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
      x(j) = amplitude * static_cast<double>(level) / steps;
      for (int i = 0; i < n; ++i) commands_[static_cast<std::size_t>(i)] = setup_->p0()(i) + x(i);
      MoveAll(commands_, {-1, j * 2 * steps + k});
      Eigen::VectorXd f(n);
      for (int i = 0; i < n; ++i) f(i) = last_[static_cast<std::size_t>(i)].force;
      out.samples.emplace_back(x, f);
    }
  }
  // f = K_a x with K_a symmetric: unknowns K_ij, i ≤ j; one equation per force sample.
  const int unknowns = n * (n + 1) / 2;
  const auto rows = static_cast<Eigen::Index>(out.samples.size()) * n;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(rows, unknowns);
  Eigen::VectorXd b(rows);
  auto index = [n](int i, int j) {
    if (i > j) std::swap(i, j);
    return i * n - i * (i - 1) / 2 + (j - i);
  };
  Eigen::Index row = 0;
  for (const auto& [x, f] : out.samples) {
    for (int i = 0; i < n; ++i, ++row) {
      for (int j = 0; j < n; ++j) a(row, index(i, j)) += x(j);
      b(row) = f(i);
    }
  }
  const Eigen::VectorXd kv = a.colPivHouseholderQr().solve(b);
  out.actuator_k.resize(n, n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) out.actuator_k(i, j) = kv(index(i, j));
  }
  const Eigen::MatrixXd& t0 = setup_->linearisation();
  out.k0 = t0.transpose() * out.actuator_k * t0;
  if (!out.k0.allFinite() || !(out.k0.diagonal().minCoeff() > 0.0)) {
    throw Error(fmt::format("{}: the stiffness ramps gave a K0 with a non-positive or non-finite "
                            "diagonal; check the specimen, the setup's transform and the load "
                            "cells, or give initial_stiffness as a matrix in N/m", name_));
  }
  SetInitialStiffness(out.k0);
  gate_.SetStiffness(out.actuator_k);  // measured: better than T⁺ᵀ K0 T⁺ when n > m
  return out;
}

nlohmann::json MultiActuatorSubstructure::SaveState() const {
  nlohmann::json last = nlohmann::json::array(), safety = nlohmann::json::array();
  for (const auto& e : last_) last.push_back({e.command, e.position, e.force, e.lab_time});
  for (int k = 0; k < num_actuators(); ++k) safety.push_back(gate_.monitor(k).SaveState());
  nlohmann::json k0 = nullptr;
  if (k0_) {
    k0 = nlohmann::json::array();
    for (Eigen::Index i = 0; i < k0_->rows(); ++i) {
      nlohmann::json r = nlohmann::json::array();
      for (Eigen::Index j = 0; j < k0_->cols(); ++j) r.push_back((*k0_)(i, j));
      k0.push_back(r);
    }
  }
  nlohmann::json actuator_k = nullptr;
  if (const auto& ka = gate_.stiffness()) {
    actuator_k = nlohmann::json::array();
    for (Eigen::Index i = 0; i < ka->rows(); ++i) {
      nlohmann::json r = nlohmann::json::array();
      for (Eigen::Index j = 0; j < ka->cols(); ++j) r.push_back((*ka)(i, j));
      actuator_k.push_back(r);
    }
  }
  return {{"last", last}, {"evaluations", evaluations_}, {"k0", k0}, {"safety", safety},
          {"actuator_k", actuator_k}, {"transfer", transfer_->SaveState()}};
}

void MultiActuatorSubstructure::RestoreState(const nlohmann::json& state) {
  const auto& last = state.at("last");
  if (last.size() != last_.size()) {
    throw Error(fmt::format("{}: the saved state has {} actuators, this setup {}", name_,
                            last.size(), last_.size()));
  }
  for (std::size_t k = 0; k < last_.size(); ++k) {
    last_[k] = {last[k][0].get<double>(), last[k][1].get<double>(), last[k][2].get<double>(),
                last[k][3].get<double>(), 0};
    gate_.monitor(static_cast<int>(k)).RestoreState(state.at("safety")[k]);
  }
  evaluations_ = state.at("evaluations").get<long>();
  if (!state.at("k0").is_null()) {
    const auto& k0 = state.at("k0");
    Eigen::MatrixXd m(static_cast<Eigen::Index>(k0.size()), static_cast<Eigen::Index>(k0.size()));
    for (std::size_t i = 0; i < k0.size(); ++i) {
      for (std::size_t j = 0; j < k0.size(); ++j) {
        m(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = k0[i][j].get<double>();
      }
    }
    SetInitialStiffness(m);
  }
  if (state.contains("actuator_k") && !state.at("actuator_k").is_null()) {
    const auto& ka = state.at("actuator_k");
    const auto n = static_cast<Eigen::Index>(num_actuators());
    Eigen::MatrixXd m(n, n);
    for (Eigen::Index i = 0; i < n; ++i) {
      for (Eigen::Index j = 0; j < n; ++j) {
        m(i, j) = ka.at(static_cast<std::size_t>(i)).at(static_cast<std::size_t>(j)).get<double>();
      }
    }
    gate_.SetStiffness(m);
  }
  if (!state.at("transfer").is_null()) transfer_->RestoreState(state.at("transfer"));
}

}  // namespace hybridtest::substructures
