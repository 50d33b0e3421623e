// PhysicalSubstructure: the checkpoint state (see physical_substructure.h and docs/safety.md,
// "Resuming a run").
#include <fmt/format.h>

#include "hybridtest/common/error.h"
#include "hybridtest/substructures/physical_substructure.h"

namespace hybridtest::substructures {
namespace {

// Rows of numbers as a rows × cols matrix; throws Error naming `what` if the sizes differ.
Eigen::MatrixXd MatrixFromJson(const nlohmann::json& rows, Eigen::Index n_rows,
                               Eigen::Index n_cols, const std::string& what) {
  if (!rows.is_array() || static_cast<Eigen::Index>(rows.size()) != n_rows) {
    throw Error(fmt::format("{}: expected {} rows of {} numbers, got {}", what, n_rows, n_cols,
                            rows.dump()));
  }
  Eigen::MatrixXd m(n_rows, n_cols);
  for (Eigen::Index i = 0; i < n_rows; ++i) {
    const auto& row = rows.at(static_cast<std::size_t>(i));
    if (static_cast<Eigen::Index>(row.size()) != n_cols) {
      throw Error(fmt::format("{}: expected {} rows of {} numbers, got {}", what, n_rows, n_cols,
                              rows.dump()));
    }
    for (Eigen::Index j = 0; j < n_cols; ++j) m(i, j) = row.at(static_cast<std::size_t>(j)).get<double>();
  }
  return m;
}

}  // namespace

nlohmann::json PhysicalSubstructure::SaveState() const {
  nlohmann::json last = nlohmann::json::array(), safety = nlohmann::json::array();
  for (const auto& e : last_) last.push_back({e.command, e.position, e.force, e.lab_time});
  for (int k = 0; k < num_actuators(); ++k) safety.push_back(gate_.monitor(k).SaveState());
  return {{"last", last},
          {"evaluations", evaluations_},
          {"k0", k0_ ? MatrixJson(*k0_) : nlohmann::json(nullptr)},
          {"safety", safety},
          {"actuator_k", actuator_k_ ? MatrixJson(*actuator_k_) : nlohmann::json(nullptr)},
          {"transfer", transfer_->SaveState()}};
}

void PhysicalSubstructure::RestoreState(const nlohmann::json& state) {
  const auto n = static_cast<Eigen::Index>(num_actuators());
  const auto m = static_cast<Eigen::Index>(num_slots());
  auto use_actuator_k = [&](const Eigen::MatrixXd& ka) {
    actuator_k_ = ka;
    if (n > 1) gate_.SetStiffness(ka);  // one actuator: in its monitor's state
  };
  try {
    const auto& last = state.at("last");
    if (last.is_object()) {
      // A one-actuator state saved before the two widths were one.
      if (n != 1 || m != 1) {
        throw Error(fmt::format("{}: the saved state is of one actuator and one slot, this "
                                "setup has {} actuators and {} slots", name_, n, m));
      }
      last_[0] = {last.at("command_m").get<double>(), last.at("position_m").get<double>(),
                  last.at("force_N").get<double>(), last.at("lab_time_s").get<double>(), 0};
      evaluations_ = state.at("evaluations").get<long>();
      if (!state.at("k0").is_null()) {
        k0_ = Eigen::MatrixXd::Constant(1, 1, state.at("k0").get<double>());
        use_actuator_k(setup_->ActuatorStiffness(*k0_));
      }
      gate_.monitor(0).RestoreState(state.at("safety"));
    } else {
      if (static_cast<Eigen::Index>(last.size()) != n) {
        throw Error(fmt::format("{}: the saved state has {} actuators, this setup {}", name_,
                                last.size(), n));
      }
      for (std::size_t k = 0; k < last_.size(); ++k) {
        last_[k] = {last[k].at(0).get<double>(), last[k].at(1).get<double>(),
                    last[k].at(2).get<double>(), last[k].at(3).get<double>(), 0};
      }
      evaluations_ = state.at("evaluations").get<long>();
      if (!state.at("k0").is_null()) {
        k0_ = MatrixFromJson(state.at("k0"), m, m, name_ + ": saved k0");
        use_actuator_k(setup_->ActuatorStiffness(*k0_));
      }
      if (state.contains("actuator_k") && !state.at("actuator_k").is_null()) {
        use_actuator_k(MatrixFromJson(state.at("actuator_k"), n, n, name_ + ": saved actuator_k"));
      }
      const auto& safety = state.at("safety");
      for (std::size_t k = 0; k < last_.size(); ++k) {
        gate_.monitor(static_cast<int>(k)).RestoreState(safety.at(k));
      }
    }
    if (!state.at("transfer").is_null()) transfer_->RestoreState(state.at("transfer"));
  } catch (const nlohmann::json::exception& e) {
    throw Error(fmt::format("{}: cannot restore the saved state: {}", name_, e.what()));
  }
}

}  // namespace hybridtest::substructures
