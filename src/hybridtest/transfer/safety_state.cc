// SafetyMonitor::SaveState/RestoreState (see safety.h).
#include <fmt/format.h>

#include "hybridtest/transfer/safety.h"

namespace hybridtest::transfer {

nlohmann::json SafetyMonitor::SaveState() const {
  nlohmann::json history = nlohmann::json::array();
  for (const auto& h : history_) {
    history.push_back({h.step, h.stage, h.command, h.position, h.force, h.answered});
  }
  return {{"has_safe_command", has_safe_command_}, {"last_safe_command_m", last_safe_command_},
          {"has_measurement", has_measurement_},   {"last_position_m", last_position_},
          {"last_force_N", last_force_},           {"has_secant", has_secant_},
          {"secant_stiffness_N_per_m", secant_stiffness_},
          {"initial_stiffness_N_per_m", initial_stiffness_},
          {"history", history}};
}

void SafetyMonitor::RestoreState(const nlohmann::json& state) {
  try {
    has_safe_command_ = state.at("has_safe_command").get<bool>();
    last_safe_command_ = state.at("last_safe_command_m").get<double>();
    has_measurement_ = state.at("has_measurement").get<bool>();
    last_position_ = state.at("last_position_m").get<double>();
    last_force_ = state.at("last_force_N").get<double>();
    has_secant_ = state.at("has_secant").get<bool>();
    secant_stiffness_ = state.at("secant_stiffness_N_per_m").get<double>();
    initial_stiffness_ = state.at("initial_stiffness_N_per_m").get<double>();
    history_.clear();
    for (const auto& h : state.at("history")) {
      history_.push_back({h.at(0).get<long>(), h.at(1).get<int>(), h.at(2).get<double>(),
                          h.at(3).get<double>(), h.at(4).get<double>(), h.at(5).get<bool>()});
    }
  } catch (const nlohmann::json::exception& e) {
    throw Error(fmt::format("safety monitor: cannot restore its state: {}", e.what()));
  }
}

}  // namespace hybridtest::transfer
