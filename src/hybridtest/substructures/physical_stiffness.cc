// PhysicalSubstructure: how K0 is known (configured, measured by a ramp, or from the safety
// section's specimen stiffness) and what the gate predicts forces with (see
// physical_substructure.h).
#include <Eigen/Dense>
#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "hybridtest/common/error.h"
#include "hybridtest/substructures/physical_substructure.h"

namespace hybridtest::substructures {

std::optional<Eigen::MatrixXd> PhysicalSubstructure::initial_stiffness() const {
  if (k0_) return k0_;
  // The safety section's stiffness is force per actuator displacement; r per d differs by the
  // setup's signs and scales.
  if (safety_stiffness_) {
    const auto n = static_cast<Eigen::Index>(num_actuators());
    return setup_->SlotStiffness(*safety_stiffness_ * Eigen::MatrixXd::Identity(n, n));
  }
  return std::nullopt;
}

void PhysicalSubstructure::SetSafetyStiffness(double actuator_stiffness) {
  for (int k = 0; k < num_actuators(); ++k) gate_.monitor(k).SetInitialStiffness(actuator_stiffness);
  safety_stiffness_ = actuator_stiffness;
}

void PhysicalSubstructure::SetInitialStiffness(const Eigen::MatrixXd& k0) {
  if (k0.rows() != num_slots() || k0.cols() != num_slots() || !k0.allFinite()) {
    throw ConfigError(fmt::format("{}: initial stiffness of {} × {}: expected a finite {} × {} "
                                  "matrix in N/m", name_, k0.rows(), k0.cols(), num_slots(),
                                  num_slots()));
  }
  k0_ = k0;
  UseActuatorStiffness(setup_->ActuatorStiffness(k0));
}

void PhysicalSubstructure::UseActuatorStiffness(const Eigen::MatrixXd& actuator_k) {
  actuator_k_ = actuator_k;
  if (num_actuators() == 1) {
    // One actuator: its monitor predicts from its own secant, from K_a until it has one.
    if (actuator_k(0, 0) > 0.0) gate_.monitor(0).SetInitialStiffness(actuator_k(0, 0));
  } else {
    gate_.SetStiffness(actuator_k);  // the coupled prediction f_last + K_a (a − x_last)
  }
}

PhysicalSubstructure::StiffnessMeasurement PhysicalSubstructure::MeasureInitialStiffness(
    double amplitude) {
  if (!(amplitude > 0.0) || !std::isfinite(amplitude)) {
    throw ConfigError(fmt::format("{}: stiffness ramp amplitude {} m: expected a positive length",
                                  name_, amplitude));
  }
  if (num_actuators() == 1 && num_slots() == 1) return MeasureSlotRamp(amplitude);
  return MeasureActuatorRamps(amplitude);
}

PhysicalSubstructure::StiffnessMeasurement PhysicalSubstructure::MeasureSlotRamp(
    double amplitude) {
  // Moves of at most half the increment limit, at least 4 up and 4 down.
  const double step_limit = 0.5 * max_displacement_increment();
  const int steps = std::max(4, static_cast<int>(std::ceil(amplitude / step_limit)));
  StiffnessMeasurement out;
  out.amplitude = amplitude;
  for (int k = 1; k <= 2 * steps; ++k) {
    const int level = k <= steps ? k : 2 * steps - k;
    const double d = amplitude * static_cast<double>(level) / steps;
    double r = 0.0;
    // Labelled step −1: before the test's first step.
    Trial({&d, 1}, {&r, 1}, {-1, k, 0.0});
    out.samples.emplace_back(Eigen::VectorXd::Constant(1, d), Eigen::VectorXd::Constant(1, r));
  }
  double sdd = 0.0, sdr = 0.0, sd = 0.0, sr = 0.0;
  const double count = static_cast<double>(out.samples.size());
  for (const auto& [d, r] : out.samples) {
    sd += d(0);
    sr += r(0);
  }
  for (const auto& [d, r] : out.samples) {
    sdd += (d(0) - sd / count) * (d(0) - sd / count);
    sdr += (d(0) - sd / count) * (r(0) - sr / count);
  }
  const double k0 = sdr / sdd;
  if (!(k0 > 0.0) || !std::isfinite(k0)) {
    throw Error(fmt::format("{}: the stiffness ramp (0 → {} m → 0, {} samples) gave K0 = {} N/m; "
                            "expected a positive stiffness: check the specimen, the setup's signs "
                            "and the load cell, or give initial_stiffness in N/m",
                            name_, amplitude, out.samples.size(), k0));
  }
  out.k0 = Eigen::MatrixXd::Constant(1, 1, k0);
  SetInitialStiffness(out.k0);
  out.actuator_k = *actuator_k_;
  return out;
}

PhysicalSubstructure::StiffnessMeasurement PhysicalSubstructure::MeasureActuatorRamps(
    double amplitude) {
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
  out.k0 = setup_->SlotStiffness(out.actuator_k);
  if (!out.k0.allFinite() || !(out.k0.diagonal().minCoeff() > 0.0)) {
    throw Error(fmt::format("{}: the stiffness ramps gave a K0 with a non-positive or non-finite "
                            "diagonal; check the specimen, the setup's transform and the load "
                            "cells, or give initial_stiffness as a matrix in N/m", name_));
  }
  SetInitialStiffness(out.k0);
  UseActuatorStiffness(out.actuator_k);  // measured: better than T⁺ᵀ K0 T⁺ when n > m
  return out;
}

void PhysicalSubstructure::MeasureRequestedStiffness(nlohmann::json& entry) {
  const bool scalar = num_actuators() == 1 && num_slots() == 1;
  if (k0_ramp_) {
    const StiffnessMeasurement m = MeasureInitialStiffness(*k0_ramp_);
    nlohmann::json samples = nlohmann::json::array();
    if (scalar) {
      for (const auto& [d, r] : m.samples) samples.push_back({d(0), r(0)});
      entry.update({{"k0", m.k0(0, 0)}, {"source", "measured"}, {"amplitude_m", m.amplitude},
                    {"samples_d_m_r_N", samples}});
    } else {
      for (const auto& [x, f] : m.samples) {
        samples.push_back({std::vector<double>(x.data(), x.data() + x.size()),
                           std::vector<double>(f.data(), f.data() + f.size())});
      }
      entry.update({{"k0", MatrixJson(m.k0)}, {"source", "measured"},
                    {"actuator_stiffness_N_per_m", MatrixJson(m.actuator_k)},
                    {"amplitude_m", m.amplitude}, {"samples_x_m_f_N", samples}});
    }
  } else if (scalar) {
    Substructure::MeasureRequestedStiffness(entry);
  } else if (const auto k0 = initial_stiffness()) {
    entry.update({{"k0", MatrixJson(*k0)}, {"source", "configured"}});
  } else {
    entry.update({{"k0", nullptr}, {"source", "unknown"}});
  }
  // The setup K0 is seen through: a measured K0 is T0ᵀ K_a T0 with T0 = J(0) [m/m].
  if (!scalar) {
    entry["setup"] = {{"kind", setup_->kind()}, {"description", setup_->Describe()},
                      {"T0", MatrixJson(setup_->linearisation())}};
  }
}

}  // namespace hybridtest::substructures
