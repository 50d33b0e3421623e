// HybridTest: the run state it saves and the start of a resumed run (see hybrid_test.h,
// run_state.h and docs/safety.md, "Resuming a run").
#include <fmt/core.h>

#include <optional>

#include "hybridtest/common/error.h"
#include "hybridtest/io/journal.h"
#include "hybridtest/io/utc_time.h"
#include "hybridtest/runner/hybrid_test.h"
#include "hybridtest/substructures/physical_substructure.h"

namespace hybridtest::runner {
namespace {
// The commands slot `s`'s bench had received when the previous session stopped, if recorded.
std::optional<long> CommandsReceivedAtStop(const nlohmann::json& sidecar, std::size_t s) {
  const auto stats = sidecar.find("statistics");
  if (stats == sidecar.end() || !stats->is_object()) return std::nullopt;
  const auto stop = stats->find("stop");
  if (stop == stats->end() || !stop->is_object()) return std::nullopt;
  const auto received = stop->find("commands_received");
  if (received == stop->end() || !received->is_array() || s >= received->size() ||
      !(*received)[s].is_number_integer()) {
    return std::nullopt;
  }
  return (*received)[s].get<long>();
}
}  // namespace

RunState HybridTest::CaptureState(const schemes::HybridScheme& scheme, long rows,
                                  long stage_rows, const nlohmann::json& statistics) const {
  RunState state;
  state.rows = rows;
  state.stage_rows = stage_rows;
  state.scheme = scheme.SaveState();
  const auto& slots = cfg_.model.model.slots();
  for (std::size_t s = 0; s < subs_.size(); ++s) {
    state.substructures.push_back({{"slot", slots[s].info.name}, {"state", subs_[s]->SaveState()}});
  }
  state.statistics = statistics;
  state.stiffness = stiffness_record_;
  state.inputs = options_.inputs;
  return state;
}

void HybridTest::RestoreSubstructures(const RunState& state) {
  const auto& slots = cfg_.model.model.slots();
  if (state.substructures.size() != subs_.size()) {
    throw ConfigError(fmt::format("the run state has {} substructures, the run's config {}",
                                  state.substructures.size(), subs_.size()));
  }
  for (std::size_t s = 0; s < subs_.size(); ++s) {
    const auto& entry = state.substructures[s];
    if (entry.value("slot", "") != slots[s].info.name) {
      throw ConfigError(fmt::format("the run state's substructure {} is slot '{}', the config's "
                                    "is '{}'", s, entry.value("slot", ""), slots[s].info.name));
    }
    subs_[s]->RestoreState(entry.at("state"));
  }
}

void HybridTest::ResumeFrom(const RunState& state, schemes::HybridScheme& scheme,
                            io::Journal& journal, const std::function<void()>& write_row,
                            const std::function<void(long, int, double)>& stage_row) {
  scheme.RestoreState(state.scheme);
  stiffness_record_ = state.stiffness;
  wall_offset_ = state.statistics.value("wall_time_s", 0.0);
  const schemes::CommittedPoint& p = scheme.committed();
  stats_.steps = p.step;
  // The state is saved just before its row: a crash in between lost only that row.
  bool row_rewritten = false;
  if (journal.rows() == state.rows - 1) {
    write_row();
    row_rewritten = true;
  } else if (journal.rows() != state.rows) {
    throw IoError(fmt::format("{}: {} rows, but the run state belongs to row {}; the journal "
                              "and its state do not fit together", journal.csv_path(),
                              journal.rows(), state.rows - 1));
  }
  nlohmann::json record = options_.resume_record;
  record.update({{"time", io::UtcNowIso8601()}, {"step", p.step}, {"t", p.t},
                 {"row", state.rows - 1},
                 {"rows_cut", rows_cut_},
                 {"row_rewritten_from_state", row_rewritten},
                 {"previous_status", journal.previous_status()}});
  if (journal.sidecar().contains("statistics") &&
      journal.sidecar()["statistics"].contains("stop")) {
    const auto& stop = journal.sidecar()["statistics"]["stop"];
    record["previous_stop"] = {{"kind", stop.value("kind", "")},
                               {"message", stop.value("message", "")}};
  }
  // Physical slots: the bench is brought back to the last committed command and checked.
  nlohmann::json checks = nlohmann::json::array();
  nlohmann::json resumes = journal.sidecar().value("resumes", nlohmann::json::array());
  const auto& slots = cfg_.model.model.slots();
  try {
  for (std::size_t s = 0; s < subs_.size(); ++s) {
    auto* physical = dynamic_cast<substructures::PhysicalSubstructure*>(subs_[s].get());
    if (physical == nullptr) continue;
    if (const auto count = CommandsReceivedAtStop(journal.sidecar(), s)) {
      physical->NoteCommandsBeforeResume(*count);
    }
    const auto check = physical->ReimposeCommitted(
        options_.resume_force_tolerance, options_.resume_position_tolerance, p.step,
        [&](bool reimposition) { stage_row(p.step, reimposition ? -1 : -2, p.t); });
    nlohmann::json c = {{"slot", slots[s].info.name},     {"command_m", check.command},
                        {"committed_force_N", check.committed_force},
                        {"ramp_moves", check.ramp_moves}, {"position_m", check.position},
                        {"force_N", check.force},         {"tolerance_N", check.tolerance},
                        {"committed_position_m", check.committed_position},
                        {"position_tolerance_m", check.position_tolerance}};
    c["read_position_m"] = check.read_position ? nlohmann::json(*check.read_position) : nullptr;
    c["read_force_N"] = check.read_force ? nlohmann::json(*check.read_force) : nullptr;
    checks.push_back(c);
  }
  } catch (const std::exception& e) {
    // A refused resume is recorded too; the run's status then says why it stopped.
    record["checks"] = checks;
    record["refused"] = e.what();
    resumes.push_back(record);
    journal.SetSidecarEntry("resumes", resumes);
    throw;
  }
  record["checks"] = checks;
  resumes.push_back(record);
  journal.SetSidecarEntry("resumes", resumes);
}

}  // namespace hybridtest::runner
