// Checkpoint state of the emulated bench and its parts (see emulated_bench.h, actuator.h,
// load_cell.h, lab_clock.h).
#include <fmt/format.h>

#include <algorithm>
#include <sstream>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/actuator.h"
#include "hybridtest/transfer/emulated_bench.h"
#include "hybridtest/transfer/lab_clock.h"
#include "hybridtest/transfer/load_cell.h"

namespace hybridtest::transfer {

nlohmann::json Actuator::SaveState() const {
  nlohmann::json state = {
      {"reference_m", reference_}, {"delayed_reference_m", delayed_reference_},
      {"delay_line_m", std::vector<double>(delay_line_.begin(), delay_line_.end())},
      {"position_m", position_}, {"velocity_m_per_s", velocity_}};
  if (shaped_) {
    state["shaper_line_m"] = std::vector<double>(shaper_line_.begin(), shaper_line_.end());
  }
  return state;
}

void Actuator::RestoreState(const nlohmann::json& state) {
  const auto line = state.at("delay_line_m").get<std::vector<double>>();
  if (line.size() != delay_line_.size()) {
    throw Error(fmt::format("emulated actuator: the saved delay line has {} entries, this "
                            "actuator {}: the bench config changed", line.size(),
                            delay_line_.size()));
  }
  reference_ = state.at("reference_m").get<double>();
  delayed_reference_ = state.at("delayed_reference_m").get<double>();
  delay_line_.assign(line.begin(), line.end());
  position_ = state.at("position_m").get<double>();
  velocity_ = state.at("velocity_m_per_s").get<double>();
  if (shaped_) {
    const auto shaper = state.at("shaper_line_m").get<std::vector<double>>();
    if (shaper.size() != shaper_line_.size()) {
      throw Error(fmt::format("emulated actuator: the saved input shaper has {} entries, this "
                              "actuator {}: the bench config changed", shaper.size(),
                              shaper_line_.size()));
    }
    shaper_line_.assign(shaper.begin(), shaper.end());
  }
}

std::string LoadCell::SaveState() const {
  std::ostringstream out;
  out << generator_ << ' ' << normal_;
  return out.str();
}

void LoadCell::RestoreState(const std::string& state) {
  std::istringstream in(state);
  in >> generator_ >> normal_;
  if (!in) throw Error("emulated load cell: cannot read the saved generator state");
}

void LabClock::Restore(double lab_time) {
  lab_time_ = lab_time;
  if (started_) {
    origin_ = std::chrono::steady_clock::now() -
              std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                  std::chrono::duration<double>(lab_time));
  }
}

nlohmann::json EmulatedBench::SaveState() const {
  if (num_actuators() == 1) {
    return {{"kind", "emulated"},
            {"command_count", command_count_},
            {"faults_fired_through", faults_fired_through_},
            {"lab_time_s", clock_->lab_time()},
            {"actuator", actuators_[0]->SaveState()},
            {"specimen", specimen_->SaveState()},
            {"load_cell", load_cells_[0]->SaveState()},
            {"safety", safety_[0].SaveState()}};
  }
  nlohmann::json actuators = nlohmann::json::array(), cells = nlohmann::json::array(),
                 safety = nlohmann::json::array();
  for (std::size_t k = 0; k < actuators_.size(); ++k) {
    actuators.push_back(actuators_[k]->SaveState());
    cells.push_back(load_cells_[k]->SaveState());
    safety.push_back(safety_[k].SaveState());
  }
  return {{"kind", "multi_emulated"}, {"command_count", command_count_},
          {"faults_fired_through", faults_fired_through_}, {"lab_time_s", clock_->lab_time()},
          {"actuators", actuators}, {"load_cells", cells}, {"safety", safety},
          {"specimen", specimen_->SaveState()}};
}

void EmulatedBench::RestoreState(const nlohmann::json& state) {
  try {
    const std::size_t n = actuators_.size();
    // (The kind read by hand: GCC 12 warns -Wnull-dereference inside json::value(key, "").)
    std::string kind;
    if (const auto it = state.find("kind"); it != state.end() && it->is_string()) {
      kind = it->get_ref<const std::string&>();
    }
    if (n == 1 && kind == "emulated") {  // the form of one actuator
      actuators_[0]->RestoreState(state.at("actuator"));
      load_cells_[0]->RestoreState(state.at("load_cell").get<std::string>());
      safety_[0].RestoreState(state.at("safety"));
    } else if (kind == "multi_emulated" && state.at("actuators").size() == n &&
               state.at("load_cells").size() == n && state.at("safety").size() == n) {
      for (std::size_t k = 0; k < n; ++k) {
        actuators_[k]->RestoreState(state.at("actuators")[k]);
        load_cells_[k]->RestoreState(state.at("load_cells")[k].get<std::string>());
        safety_[k].RestoreState(state.at("safety")[k]);
      }
    } else {
      throw Error(fmt::format("it is not the state of an emulated bench with {} actuator{}", n,
                              n == 1 ? "" : "s"));
    }
    specimen_->RestoreState(state.at("specimen"));
    clock_->Restore(state.at("lab_time_s").get<double>());
    command_count_ = state.at("command_count").get<long>();
    // A test fault (bench_faults.h) at a command received before the run stopped has fired
    // and does not fire again after the resume.
    faults_fired_through_ = std::max(state.value("faults_fired_through", 0L),
                                     state.value("commands_received_at_stop", 0L));
  } catch (const nlohmann::json::exception& e) {
    throw Error(fmt::format("emulated bench: cannot restore its state: {}", e.what()));
  }
}

std::optional<std::vector<Measurement>> EmulatedBench::ReadAll() {
  const std::size_t n = actuators_.size();
  std::vector<double> deformation(n);
  for (std::size_t k = 0; k < n; ++k) {
    deformation[k] = actuators_[k]->position() - spec_.actuators[k].p0;
  }
  // The specimen's forces at the committed state: a trial of a copy of its law (the committed
  // state is untouched).
  auto law = specimen_->Clone();
  std::vector<double> force(n);
  law->Trial(deformation, force);
  std::vector<Measurement> out;
  for (std::size_t k = 0; k < n; ++k) {
    const EmulatedBenchConfig& a = spec_.actuators[k];
    out.push_back(Measurement{actuators_[k]->position() / a.units.metres_per_length_unit,
                              (force[k] + a.offset) / a.units.newtons_per_force_unit,
                              clock_->lab_time(), 0});
  }
  return out;
}

BenchAnnouncement EmulatedBench::Announce() const {
  BenchAnnouncement a{{}, "the emulated bench"};
  for (const auto& actuator : spec_.actuators) a.actuators.push_back({actuator.p0, actuator.safety});
  return a;
}

std::optional<ProbeReading> EmulatedBench::Probe() {
  const char* state = state_ == State::kHolding       ? "holding"
                      : state_ == State::kActive      ? "active"
                      : state_ == State::kDeactivated ? "deactivated"
                                                      : "configured, not yet activated";
  return ProbeReading{*ReadAll(), std::string("emulated bench ") + state, ""};
}

}  // namespace hybridtest::transfer
