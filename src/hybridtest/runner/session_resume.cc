// Session: continuing a run from its saved state (see session.h, run_state.h and
// docs/safety.md, "Resuming a run").
#include <fmt/core.h>

#include "hybridtest/common/error.h"
#include "hybridtest/runner/session.h"
#include "hybridtest/schemes/scheme_config.h"
#include "hybridtest/substructures/multi_actuator_substructure.h"
#include "hybridtest/substructures/physical_substructure.h"

namespace hybridtest::runner {

void Session::RestoreFromState() {
  const RunState& state = *resume_;
  for (std::size_t s = 0; s < subs_.size(); ++s) {
    subs_[s]->RestoreState(state.substructures[s].at("state"));
  }
  BuildScheme();  // after the substructures are restored: K0 may have been measured
  scheme_->RestoreState(state.scheme);
  stiffness_record_ = state.stiffness;
  wall_offset_ = state.statistics.value("wall_time_s", 0.0);
  const schemes::CommittedPoint& p = scheme_->committed();
  stats_.steps = p.step;
  stats_.rows = state.rows;
  // The state's committed row, as the restored scheme and substructures give it; the file
  // observer writes it if a crash lost it.
  FillRow(p.t, p.x, p.r, true);
  {
    ResumeEvent event;
    event.phase = ResumeEvent::kRestored;
    event.state = &state;
    event.row = {row_.data(), static_cast<std::size_t>(row_.size())};
    for (SessionObserver* o : observers_) o->OnResume(event);
  }
  ReimposeCommitted();
}

void Session::ReimposeCommitted() {
  const RunState& state = *resume_;
  const schemes::CommittedPoint& p = scheme_->committed();
  ResumeEvent event;
  event.state = &state;
  const Eigen::VectorXd none;  // resume moves carry no slot displacements or forces
  try {
    for (std::size_t s = 0; s < subs_.size(); ++s) {
      const std::string& name = spec_.substructures[s].slot;
      if (auto* multi = dynamic_cast<substructures::MultiActuatorSubstructure*>(subs_[s].get())) {
        // Every actuator walked back from where it is and re-imposed together; every
        // position and force checked. One record per actuator, named like its channels.
        const auto check = multi->ReimposeCommitted(
            spec_.resume.force_tolerance.value_or(0.0),
            spec_.resume.position_tolerance.value_or(0.0), p.step, [&](bool reimposition) {
              PublishTrial({p.step, reimposition ? -1 : -2, p.t}, none, none);
            });
        for (std::size_t k = 0; k < check.actuators.size(); ++k) {
          const auto& a = check.actuators[k];
          nlohmann::json c = {{"slot", fmt::format("{}_a{}", name, k + 1)},
                              {"actuator", k + 1},
                              {"command_m", a.command},
                              {"committed_force_N", a.committed_force},
                              {"ramp_moves", check.ramp_moves},
                              {"position_m", a.position},
                              {"force_N", a.force},
                              {"tolerance_N", a.force_tolerance},
                              {"committed_position_m", a.committed_position},
                              {"position_tolerance_m", a.position_tolerance}};
          c["read_position_m"] = a.read_position ? nlohmann::json(*a.read_position) : nullptr;
          c["read_force_N"] = a.read_force ? nlohmann::json(*a.read_force) : nullptr;
          event.checks.push_back(c);
        }
        continue;
      }
      auto* physical = dynamic_cast<substructures::PhysicalSubstructure*>(subs_[s].get());
      if (physical == nullptr) continue;
      if (s < options_.commands_received_at_stop.size() &&
          options_.commands_received_at_stop[s]) {
        physical->NoteCommandsBeforeResume(*options_.commands_received_at_stop[s]);
      }
      const auto check = physical->ReimposeCommitted(
          spec_.resume.force_tolerance.value_or(0.0),
          spec_.resume.position_tolerance.value_or(0.0), p.step, [&](bool reimposition) {
            PublishTrial({p.step, reimposition ? -1 : -2, p.t}, none, none);
          });
      nlohmann::json c = {{"slot", name},     {"command_m", check.command},
                          {"committed_force_N", check.committed_force},
                          {"ramp_moves", check.ramp_moves}, {"position_m", check.position},
                          {"force_N", check.force},         {"tolerance_N", check.tolerance},
                          {"committed_position_m", check.committed_position},
                          {"position_tolerance_m", check.position_tolerance}};
      c["read_position_m"] = check.read_position ? nlohmann::json(*check.read_position) : nullptr;
      c["read_force_N"] = check.read_force ? nlohmann::json(*check.read_force) : nullptr;
      event.checks.push_back(c);
    }
  } catch (const std::exception& e) {
    // A refused resume is recorded too; the run's status then says why it stopped.
    event.phase = ResumeEvent::kRefused;
    event.refused = e.what();
    for (SessionObserver* o : observers_) o->OnResume(event);
    throw;
  }
  event.phase = ResumeEvent::kChecked;
  for (SessionObserver* o : observers_) o->OnResume(event);
}

}  // namespace hybridtest::runner
