// Session: how each substructure's K0 is known before the test (measured by a ramp, configured
// or from its law), for the schemes and the sidecar (see session.h).
#include <fmt/core.h>

#include <limits>

#include "hybridtest/runner/session.h"
#include "hybridtest/runner/slot_info.h"

namespace hybridtest::runner {

// See slot_info.h. A coupled K0 holds each block's matrix; the other slots sit on its diagonal.
schemes::SlotInfo SlotInfoOf(const std::vector<std::unique_ptr<substructures::Substructure>>& subs,
                             const std::vector<std::vector<int>>& slot_of, int num_slots) {
  const auto m = static_cast<Eigen::Index>(num_slots);
  schemes::SlotInfo info{Eigen::VectorXd::Zero(m), Eigen::VectorXd::Zero(m), {}};
  for (std::size_t s = 0; s < subs.size(); ++s) {
    const auto& slots = slot_of[s];
    const auto k0 = subs[s]->initial_stiffness();
    if (slots.size() == 1) {
      info.k0(slots[0]) = k0 ? (*k0)(0, 0) : std::numeric_limits<double>::quiet_NaN();
    } else {
      // A coupled K0: the full matrix, the other slots on its diagonal.
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
    // Each substructure measures (a ramp, if its config asks) or tells its K0.
    nlohmann::json entry = {{"slot", spec_.substructures[s].slot}};
    subs_[s]->MeasureRequestedStiffness(entry);
    if (slot_of_[s].size() > 1 || subs_[s]->num_actuators() > 1) {
      entry["slots"] = spec_.substructures[s].SlotNames();
    }
    stiffness_record_.push_back(entry);
  }
}

}  // namespace hybridtest::runner
