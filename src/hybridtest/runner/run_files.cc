// See run_files.h.
#include "hybridtest/runner/run_files.h"

#include <fmt/core.h>

#include <filesystem>

#include "hybridtest/common/error.h"
#include "hybridtest/io/run_outputs.h"
#include "hybridtest/io/utc_time.h"
#include "hybridtest/runner/run_record.h"

namespace hybridtest::runner {

RunFiles::RunFiles(const io::RunSpec& spec, nlohmann::json resume_record)
    : spec_(spec), resume_record_(std::move(resume_record)) {}

void RunFiles::OnStart(const StartEvent& event) {
  const std::string& csv = spec_.output.csv_path;
  const auto& subs = event.substructures;
  const bool physical = event.has_physical;
  physical_ = physical;
  // A paced (real-time) run cannot wait for a sync between ticks: its specimen moves on its
  // own clock, so its rows are buffered like a numerical run's (docs/real-time.md).
  const io::SyncPolicy policy = physical && !spec_.real_time.enabled ? io::SyncPolicy::kEveryRow
                                                                     : io::SyncPolicy::kBuffered;
  const RunState* resume = event.resume;
  if (resume != nullptr) {
    rows_cut_ = CutJournalToRows(csv, resume->rows);
    journal_.emplace(io::kReopenForAppend, csv, policy);
    state_rows_ = resume->rows;
    resume_uncommitted_ = true;
  } else {
    io::JournalMetadata metadata = JournalMetadataFor(spec_, subs, spec_.output.command);
    metadata.extra["inputs"] = spec_.source.inputs;
    journal_.emplace(csv, JournalChannels(spec_), std::move(metadata), policy);
  }
  if (physical && spec_.output.record_stages) {
    // Flushed to the kernel every row (a killed process loses nothing); synced to the disk in
    // batches: the journal itself is synced every row.
    if (resume != nullptr && std::filesystem::exists(io::StagesPath(csv))) {
      stages_.emplace(io::kReopenForAppend, io::StagesPath(csv), io::SyncPolicy::kBatched, 100);
    } else {
      stages_.emplace(io::StagesPath(csv), StageChannels(spec_),
                      JournalMetadataFor(spec_, subs, spec_.output.command),
                      io::SyncPolicy::kBatched, 100);
    }
    stage_values_.resize(static_cast<Eigen::Index>(stages_->channels().size()));
  }
  state_path_ = io::RunStatePath(csv);
}

void RunFiles::OnTrial(const TrialEvent& event) {
  if (!stages_) return;
  Eigen::Index c = 0;
  stage_values_(c++) = static_cast<double>(event.at.step);
  stage_values_(c++) = event.at.stage;
  stage_values_(c++) = event.at.t;
  for (const auto& e : event.exchanges) {
    for (double v : {e.command, e.position, e.force, e.lab_time,
                     static_cast<double>(e.force_reversals)}) {
      stage_values_(c++) = v;
    }
  }
  stages_->Append(std::span<const double>(stage_values_.data(), stage_values_.size()));
}

void RunFiles::OnCommit(const CommitEvent& event) {
  if (event.kind == RowKind::kCommitted) resume_uncommitted_ = false;
  if (spec_.real_time.enabled) {
    journal_->Append(event.row, event.kind == RowKind::kCommitted);
    if (event.kind == RowKind::kCommitted) {
      last_committed_.assign(event.row.begin(), event.row.end());
      last_committed_step_ = event.step;
      committed_rows_ = journal_->rows();
    }
    return;
  }
  if (event.kind != RowKind::kCommitted) {
    journal_->Append(event.row, false);
    return;
  }
  if (journal_->rows() == 0) {
    // Row 0 first: it publishes the journal; the state of a run that never published stays
    // that of the earlier run at the same path.
    journal_->Append(event.row, true);
    SaveState(event, true, journal_->rows());
    return;
  }
  SaveState(event, event.finished, journal_->rows() + 1);
  journal_->Append(event.row, true);
}

void RunFiles::SaveState(const CommitEvent& event, bool always, long rows_after) {
  if (!spec_.output.save_state) return;
  const bool every_row = physical_ && !spec_.real_time.enabled;
  if (!always && !every_row && rows_after / 1000 == state_rows_ / 1000) return;
  if (!event.state) {
    throw Error("RunFiles: a committed row without its state (a file-backed run that is not "
                "real-time saves its state on the stepping thread)");
  }
  journal_->Flush();  // its rows before the state's are in the kernel (kBuffered holds some)
  RunState state = event.state();
  state.rows = rows_after;
  state.stage_rows = stages_ ? stages_->rows() : 0;
  state.row.assign(event.row.begin(), event.row.end());
  state.journal_rows = journal_->rows();
  if (journal_->rows() > 0) state.journal_last_row = journal_->last_row();
  SaveRunState(state_path_, state);
  state_rows_ = rows_after;
}

void RunFiles::OnResume(const ResumeEvent& event) {
  const RunState& state = *event.state;
  if (event.phase == ResumeEvent::kRestored) {
    // The state is saved just before its row: a crash in between lost only that row.
    if (journal_->rows() == state.rows - 1) {
      journal_->Append(event.row, true);
      row_rewritten_ = true;
    } else if (journal_->rows() != state.rows) {
      throw IoError(fmt::format("{}: {} rows, but the run state belongs to row {}; the journal "
                                "and its state do not fit together", journal_->csv_path(),
                                journal_->rows(), state.rows - 1));
    }
    return;
  }
  nlohmann::json record = resume_record_;
  record.update({{"time", io::UtcNowIso8601()}, {"step", event.step}, {"t", event.t},
                 {"row", state.rows - 1},
                 {"rows_cut", rows_cut_},
                 {"row_rewritten_from_state", row_rewritten_},
                 {"previous_status", journal_->previous_status()}});
  const nlohmann::json& sidecar = journal_->sidecar();
  if (sidecar.contains("statistics") && sidecar["statistics"].contains("stop")) {
    const auto& stop = sidecar["statistics"]["stop"];
    record["previous_stop"] = {{"kind", stop.value("kind", "")},
                               {"message", stop.value("message", "")}};
  }
  record["checks"] = event.checks;
  resume_recorded_ = true;
  if (event.phase == ResumeEvent::kRefused) record["refused"] = event.refused;
  nlohmann::json resumes = sidecar.value("resumes", nlohmann::json::array());
  resumes.push_back(record);
  journal_->SetSidecarEntry("resumes", resumes);
}

void RunFiles::SaveRealTimeState(const StopEvent& event) {
  // The session's committed point must be the last row written (a row lost to a full queue
  // would leave the state ahead of its journal: then no state is saved).
  if (!spec_.output.save_state || !event.state || last_committed_step_ < 0 ||
      event.committed_step != last_committed_step_) {
    return;
  }
  journal_->Flush();
  RunState state = *event.state;
  state.rows = committed_rows_;
  state.stage_rows = stages_ ? stages_->rows() : 0;
  state.row = last_committed_;
  // The journal as the state describes it: through the committed row (an uncommitted row
  // after it is cut on resume).
  state.journal_rows = committed_rows_;
  state.journal_last_row = last_committed_;
  SaveRunState(state_path_, state);
  state_rows_ = committed_rows_;
}

void RunFiles::OnStop(const StopEvent& event) {
  if (!journal_) return;
  if (spec_.real_time.enabled) {
    try {
      SaveRealTimeState(event);
    } catch (const std::exception&) {
      if (event.status == SessionStatus::kFinished) throw;
    }
  }
  if (KeepPreviousStop(event)) return;
  const std::string status =
      event.status == SessionStatus::kFinished ? "completed" : "stopped: " + event.reason;
  if (event.status == SessionStatus::kFinished) {
    journal_->Finish(event.statistics, status);
    if (stages_) stages_->Finish(event.statistics, status);
    return;
  }
  try {
    journal_->Finish(event.statistics, status);
  } catch (const std::exception&) {
  }
  try {
    if (stages_) stages_->Finish(event.statistics, status);
  } catch (const std::exception&) {
  }
}

bool RunFiles::KeepPreviousStop(const StopEvent& event) {
  const nlohmann::json none = nlohmann::json::object();
  const nlohmann::json stop = event.statistics.is_object() ? event.statistics.value("stop", none) : none;
  if (!resume_uncommitted_ || event.status == SessionStatus::kFinished ||
      !journal_->published() || (stop.is_object() && stop.value("kind", "") == "safety")) {
    return false;
  }
  const nlohmann::json& sidecar = journal_->sidecar();
  nlohmann::json resumes = sidecar.value("resumes", nlohmann::json::array());
  if (!resume_recorded_ || resumes.empty()) {
    nlohmann::json record = resume_record_;
    record.update({{"time", io::UtcNowIso8601()}, {"previous_status", journal_->previous_status()}});
    resumes.push_back(record);
  }
  resumes.back()["stopped"] = {{"status", "stopped: " + event.reason}, {"stop", stop}};
  try {
    journal_->SetSidecarEntry("resumes", resumes);
    journal_->Finish(sidecar.value("statistics", none), journal_->previous_status());
  } catch (const std::exception&) {
    // The run's own error is the one reported; the earlier record stays as it was.
  }
  return true;
}

void RunFiles::OnOperatorAction(const nlohmann::json& action) {
  // Actions come between steps, after row 0 has published the journal.
  if (!journal_ || !journal_->published()) return;
  nlohmann::json actions = journal_->sidecar().value("operator_actions", nlohmann::json::array());
  actions.push_back(action);
  journal_->SetSidecarEntry("operator_actions", std::move(actions));
}

}  // namespace hybridtest::runner
