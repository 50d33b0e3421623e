// Session: continuing a run from its saved state (see session.h, run_state.h and
// docs/safety.md, "Resuming a run").
#include <fmt/core.h>

#include "hybridtest/common/error.h"
#include "hybridtest/runner/session.h"
#include "hybridtest/schemes/scheme_config.h"

namespace hybridtest::runner {

void Session::RestoreFromState() {
  const RunState& state = *resume_;
  for (std::size_t s = 0; s < subs_.size(); ++s) {
    nlohmann::json saved = state.substructures[s].at("state");
    // The commands its bench had received when the run stopped (the interrupted step's too):
    // part of what the substructure restores (substructure.h).
    if (s < options_.commands_received_at_stop.size() &&
        options_.commands_received_at_stop[s] && saved.is_object()) {
      saved["commands_received_at_stop"] = *options_.commands_received_at_stop[s];
    }
    subs_[s]->RestoreState(saved);
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
    event.step = p.step;
    event.t = p.t;
    for (SessionObserver* o : observers_) o->OnResume(event);
  }
  ReimposeCommitted();
}

void Session::ReimposeCommitted() {
  const RunState& state = *resume_;
  const schemes::CommittedPoint& p = scheme_->committed();
  ResumeEvent event;
  event.state = &state;
  event.step = p.step;
  event.t = p.t;
  const Eigen::VectorXd none;  // resume moves carry no slot displacements or forces
  try {
    for (std::size_t s = 0; s < subs_.size(); ++s) {
      if (!slot_map_.substructures[s].physical) continue;
      substructures::Substructure::ResumeRequest request;
      request.name = slot_map_.substructures[s].name;
      request.force_tolerance = spec_.resume.force_tolerance.value_or(0.0);
      request.position_tolerance = spec_.resume.position_tolerance.value_or(0.0);
      request.step = p.step;
      request.on_move = [&](bool reimposition) {
        PublishTrial({p.step, reimposition ? -1 : -2, p.t}, none, none);
      };
      for (auto& c : subs_[s]->ReimposeForResume(request)) event.checks.push_back(std::move(c));
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
