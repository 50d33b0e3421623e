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
//   row           the journal row of the committed point, value for value (t, q, u, r and
//                 every physical slot's command, position, force, lab time; NaN as null)
//   journal       the journal as it was on disk when the state was saved: {rows, last_row}
//                 (last_row: the values of its last row, null with none)
//   inputs        the files the run reads: [{role, path, sha256}], `path` relative to the
//                 journal's directory (a token file has no sha256)
//   checksum      SHA-256 of the state's JSON text without this key
//
// The state cannot lie (docs/safety.md, "Resuming a run"): LoadRunState refuses a state whose
// checksum does not match, and VerifyRunStateAgainstJournal refuses one that disagrees with
// its journal, before anything is cut or moved.
//
// When: at every commit of a run with a physical slot (the journal is synced every row); at
// the journal's batch syncs (every 1000 rows) and at the end of a numerical run — resume then
// cuts the journal back to `rows`.
#include <nlohmann/json.hpp>

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace hybridtest::runner {

struct RunState {
  long rows = 0;
  long stage_rows = 0;
  nlohmann::json scheme;
  nlohmann::json substructures = nlohmann::json::array();
  nlohmann::json statistics = nlohmann::json::object();
  nlohmann::json stiffness = nlohmann::json::array();
  std::vector<double> row;                        // the committed row's values
  // The last values of a row that are the model's constraint forces (run_record.h): derived
  // from the committed point, not part of it. Written to the JSON only when > 0.
  long constraint_forces = 0;
  long journal_rows = 0;                          // journal rows on disk at saving
  std::optional<std::vector<double>> journal_last_row;  // values of its last row
  nlohmann::json inputs = nlohmann::json::array();
};

// "<dir>/<stem>.state.json" for the journal "<dir>/<stem>.csv".
std::string RunStatePath(const std::string& csv_path);

nlohmann::json ToJson(const RunState& state);
// Throws ConfigError naming `where` (the file) if the format, the version or the checksum do
// not match, or a key is missing or has the wrong type.
RunState RunStateFromJson(const nlohmann::json& j, const std::string& where);
// The checksum a state's JSON must carry: SHA-256 of its text without "checksum".
std::string RunStateChecksum(const nlohmann::json& j);

// Resume: cuts the complete rows after the first `rows` from the CSV at csv_path (a numerical
// run's state is older than its last rows; a stop's last row is not committed) and syncs it.
// A partial last line is left to the journal's reopening. Returns the rows cut. Throws
// IoError naming the file.
long CutJournalToRows(const std::string& csv_path, long rows);

// Writes the state atomically to `path` (see above), with its checksum. Throws IoError.
void SaveRunState(const std::string& path, const RunState& state);
// Reads it back. Throws ConfigError (exit 2) naming the file if it is missing, unreadable,
// damaged, of another version, or its checksum does not match (edited or corrupted).
RunState LoadRunState(const std::string& path);

// Refuses (ConfigError, exit 2, naming the disagreement and the way out) a state that does not
// belong to the journal at csv_path: the journal must hold at least the rows it held when the
// state was saved, its row journal_rows − 1 must equal journal_last_row, and the committed row
// (row rows − 1), where the journal has it, must equal `row` value for value; where the
// journal has only rows − 1 rows (a crash between the state and its row), resume writes it.
// Reads only; nothing is cut.
void VerifyRunStateAgainstJournal(const RunState& state, const std::string& csv_path);

// Row `index` (0-based, after the header) of a CSV journal, and the number of complete rows.
struct JournalRows {
  long complete = 0;                        // rows ending in a newline
  std::map<long, std::vector<double>> rows;  // the rows asked for that exist
};
JournalRows ReadJournalRows(const std::string& csv_path, const std::vector<long>& indices);

}  // namespace hybridtest::runner
