// Session: how each substructure's K0 is known before the test (measured by a ramp, configured
// or from its law), for the schemes and the sidecar (see session.h).
#include <fmt/core.h>

#include <limits>

#include "hybridtest/runner/session.h"
#include "hybridtest/runner/slot_info.h"
#include "hybridtest/substructures/multi_actuator_substructure.h"
#include "hybridtest/substructures/physical_substructure.h"

namespace hybridtest::runner {
namespace {

nlohmann::json MatrixJson(const Eigen::MatrixXd& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    nlohmann::json row = nlohmann::json::array();
    for (Eigen::Index j = 0; j < m.cols(); ++j) row.push_back(m(i, j));
    rows.push_back(row);
  }
  return rows;
}

// A specimen on several actuators: K0 (m × m) measured, configured, or unknown.
void MultiActuatorStiffness(substructures::MultiActuatorSubstructure& multi, nlohmann::json& entry) {
  if (multi.requested_stiffness_ramp()) {
    const auto m = multi.MeasureInitialStiffness(*multi.requested_stiffness_ramp());
    nlohmann::json samples = nlohmann::json::array();
    for (const auto& [x, f] : m.samples) {
      samples.push_back({std::vector<double>(x.data(), x.data() + x.size()),
                         std::vector<double>(f.data(), f.data() + f.size())});
    }
    entry.update({{"k0", MatrixJson(m.k0)}, {"source", "measured"},
                  {"actuator_stiffness_N_per_m", MatrixJson(m.actuator_k)},
                  {"amplitude_m", m.amplitude}, {"samples_x_m_f_N", samples}});
  } else if (const auto k0 = multi.initial_stiffness_matrix()) {
    entry.update({{"k0", MatrixJson(*k0)}, {"source", "configured"}});
  } else {
    entry.update({{"k0", nullptr}, {"source", "unknown"}});
  }
  // The setup K0 is seen through: a measured K0 is T0ᵀ K_a T0 with T0 = J(0) [m/m].
  entry["setup"] = {{"kind", multi.setup().kind()}, {"description", multi.setup().Describe()},
                    {"T0", MatrixJson(multi.setup().linearisation())}};
}

}  // namespace

// See slot_info.h. A coupled K0 holds each block's matrix; the other slots sit on its diagonal.
schemes::SlotInfo SlotInfoOf(const std::vector<std::unique_ptr<substructures::Substructure>>& subs,
                             const std::vector<std::vector<int>>& slot_of, int num_slots) {
  const auto m = static_cast<Eigen::Index>(num_slots);
  schemes::SlotInfo info{Eigen::VectorXd::Zero(m), Eigen::VectorXd::Zero(m), {}};
  for (std::size_t s = 0; s < subs.size(); ++s) {
    const auto& slots = slot_of[s];
    if (slots.size() == 1) {
      info.k0(slots[0]) =
          subs[s]->initial_stiffness().value_or(std::numeric_limits<double>::quiet_NaN());
    } else {
      // A coupled K0: the full matrix, the other slots on its diagonal.
      const auto k0 = subs[s]->initial_stiffness_matrix();
      if (info.k0_matrix.size() == 0) info.k0_matrix = Eigen::MatrixXd::Zero(m, m);
      for (std::size_t i = 0; i < slots.size(); ++i) {
        for (std::size_t j = 0; j < slots.size(); ++j) {
          info.k0_matrix(slots[i], slots[j]) =
              k0 ? (*k0)(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j))
                 : std::numeric_limits<double>::quiet_NaN();
        }
        info.k0(slots[i]) = info.k0_matrix(slots[i], slots[i]);
      }
    }
    for (int i : slots) info.max_increment(i) = subs[s]->max_displacement_increment();
  }
  if (info.k0_matrix.size() > 0) {
    for (Eigen::Index i = 0; i < m; ++i) {
      if (info.k0_matrix.row(i).cwiseAbs().sum() == 0.0) info.k0_matrix(i, i) = info.k0(i);
    }
  }
  return info;
}

void Session::MeasureRequestedStiffness() {
  stiffness_record_ = nlohmann::json::array();
  for (std::size_t s = 0; s < subs_.size(); ++s) {
    nlohmann::json entry = {{"slot", spec_.substructures[s].slot}};
    if (auto* multi = dynamic_cast<substructures::MultiActuatorSubstructure*>(subs_[s].get())) {
      MultiActuatorStiffness(*multi, entry);
      entry["slots"] = spec_.substructures[s].SlotNames();
      stiffness_record_.push_back(entry);
      continue;
    }
    if (slot_of_[s].size() > 1) {
      const auto k0 = subs_[s]->initial_stiffness_matrix();
      entry.update({{"slots", spec_.substructures[s].SlotNames()},
                    {"k0", k0 ? MatrixJson(*k0) : nlohmann::json(nullptr)},
                    {"source", k0 ? "law" : "unknown"}});
      stiffness_record_.push_back(entry);
      continue;
    }
    auto* physical = dynamic_cast<substructures::PhysicalSubstructure*>(subs_[s].get());
    if (physical != nullptr && physical->requested_stiffness_ramp()) {
      const auto m = physical->MeasureInitialStiffness(*physical->requested_stiffness_ramp());
      nlohmann::json samples = nlohmann::json::array();
      for (const auto& [d, r] : m.samples) samples.push_back({d, r});
      entry.update({{"k0", m.k0}, {"source", "measured"}, {"amplitude_m", m.amplitude},
                    {"samples_d_m_r_N", samples}});
    } else if (const auto k0 = subs_[s]->initial_stiffness()) {
      entry.update({{"k0", *k0}, {"source", subs_[s]->is_physical() ? "configured" : "law"}});
    } else {
      entry.update({{"k0", nullptr}, {"source", "unknown"}});
    }
    stiffness_record_.push_back(entry);
  }
}

}  // namespace hybridtest::runner
