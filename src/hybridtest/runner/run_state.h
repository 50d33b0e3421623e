#pragma once
// RunState: everything a run needs to continue after a crash, a kill, a lost bench or a stop
// (after MuJoCo's mj_getState/mj_setState and Drake's Context): one JSON object written
// atomically (write a temporary file, fsync, rename, sync the directory) beside the journal
// as "<run>.state.json" (docs/results-format.md, "Run state"):
//
//   rows          journal rows the state belongs to: rows 0..rows−1, the last being the
//                 committed point of `scheme` (its row may be written just after the state:
//                 resume writes it from the state if a crash came in between)
//   stage_rows    rows of the stage record when the state was taken (0 without one)
//   scheme        HybridScheme::SaveState(): step, t, x, r and the scheme's own memory
//   substructures per slot: {"slot", "state": Substructure::SaveState()} (law state; safety
//                 monitor, last exchange, evaluations, K0 and an in-process bench's state)
//   statistics    the run statistics so far (steps, rows, evaluations, lab and wall time)
//   stiffness     the K0 record of the run (per slot: k0, source)
//
// When: at every commit of a run with a physical slot (the journal is synced every row); at
// the journal's batch syncs (every 1000 rows) and at the end of a numerical run — resume then
// cuts the journal back to `rows`.
#include <nlohmann/json.hpp>

#include <string>

namespace hybridtest::runner {

struct RunState {
  long rows = 0;
  long stage_rows = 0;
  nlohmann::json scheme;
  nlohmann::json substructures = nlohmann::json::array();
  nlohmann::json statistics = nlohmann::json::object();
  nlohmann::json stiffness = nlohmann::json::array();
};

// "<dir>/<stem>.state.json" for the journal "<dir>/<stem>.csv".
std::string RunStatePath(const std::string& csv_path);

nlohmann::json ToJson(const RunState& state);
// Throws IoError naming `where` (the file) if a key is missing or has the wrong type.
RunState RunStateFromJson(const nlohmann::json& j, const std::string& where);

// Resume: cuts the complete rows after the first `rows` from the CSV at csv_path (a numerical
// run's state is older than its last rows; a stop's last row is not committed) and syncs it.
// A partial last line is left to the journal's reopening. Returns the rows cut. Throws
// IoError naming the file.
long CutJournalToRows(const std::string& csv_path, long rows);

// Writes the state atomically to `path` (see above). Throws IoError.
void SaveRunState(const std::string& path, const RunState& state);
// Reads it back. Throws IoError naming the file if it is missing or unreadable.
RunState LoadRunState(const std::string& path);

}  // namespace hybridtest::runner
