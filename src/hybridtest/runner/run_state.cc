// See run_state.h.
#include "hybridtest/runner/run_state.h"

#include <fmt/core.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "hybridtest/common/error.h"
#include "hybridtest/io/atomic_file.h"
#include "hybridtest/io/digest.h"
#include "hybridtest/io/run_lock.h"
#include "hybridtest/io/run_outputs.h"

namespace hybridtest::runner {

namespace {
constexpr const char* kFormat = "hybridtest-run-state";
constexpr int kVersion = 2;

// Journal values in JSON: NaN (a slot without a sample) as null, every other value exactly
// (nlohmann prints the shortest text that reads back to the same double).
nlohmann::json RowToJson(const std::vector<double>& row) {
  nlohmann::json a = nlohmann::json::array();
  for (double v : row) a.push_back(std::isnan(v) ? nlohmann::json(nullptr) : nlohmann::json(v));
  return a;
}
std::vector<double> RowFromJson(const nlohmann::json& a) {
  std::vector<double> row;
  if (!a.is_array()) throw ConfigError("a row is not an array of numbers");
  for (const auto& v : a) {
    if (!v.is_null() && !v.is_number()) throw ConfigError("a row value is not a number");
    row.push_back(v.is_null() ? std::numeric_limits<double>::quiet_NaN() : v.get<double>());
  }
  return row;
}


// Two journal values are the same if their bits are, NaN matching NaN.
bool SameValues(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::isnan(a[i]) && std::isnan(b[i])) continue;
    if (std::memcmp(&a[i], &b[i], sizeof(double)) != 0) return false;
  }
  return true;
}

std::string Describe(const std::vector<double>& row) {
  std::string text;
  for (std::size_t i = 0; i < row.size() && i < 6; ++i) {
    text += fmt::format("{}{}", i == 0 ? "" : ",", row[i]);
  }
  return text + (row.size() > 6 ? ",..." : "");
}

// The committed point the scheme and the physical slots will be restored to must be the row
// the state records (which the journal is checked against): t, x and r of the scheme's state,
// then command, position, force and lab time of every physical slot's last exchange. A state
// whose parts disagree would move the actuator to a command that was never committed.
void CheckStateAgreesWithItsRow(const RunState& s) {
  std::vector<double> expected;
  auto number = [](const nlohmann::json& v) {
    if (v.is_null()) return std::numeric_limits<double>::quiet_NaN();
    if (!v.is_number()) throw ConfigError("a value of the committed point is not a number");
    return v.get<double>();
  };
  expected.push_back(number(s.scheme.at("t")));
  for (const char* key : {"x", "r"}) {
    const auto& a = s.scheme.at(key);
    if (!a.is_array()) throw ConfigError(fmt::format("scheme.{} is not an array", key));
    for (const auto& v : a) expected.push_back(number(v));
  }
  for (const auto& entry : s.substructures) {
    if (!entry.is_object() || !entry.contains("state") || !entry["state"].is_object() ||
        !entry["state"].contains("last")) {
      continue;  // a numerical slot has no exchange
    }
    const auto& last = entry["state"]["last"];
    if (last.is_array()) {  // several actuators: [command, position, force, lab time] each
      for (const auto& actuator : last) {
        if (!actuator.is_array() || actuator.size() < 4) {
          throw ConfigError("an actuator's last exchange is not [command, position, force, "
                            "lab time]");
        }
        for (std::size_t i = 0; i < 4; ++i) expected.push_back(number(actuator[i]));
      }
      continue;
    }
    for (const char* key : {"command_m", "position_m", "force_N", "lab_time_s"}) {
      expected.push_back(number(last.at(key)));
    }
  }
  if (!SameValues(expected, s.row)) {
    throw ConfigError(fmt::format("its committed point ({}) is not its row ({}): the parts of the "
                                  "state disagree", Describe(expected), Describe(s.row)));
  }
}

// The counters of a state and the relation between its step and its rows (the relation the
// runner writes): row 0 is step 0, and every step commits one row; a multi-rate scheme
// (mr-os) also journals its substeps as intermediate rows, so its rows may exceed step + 1.
// Counters are never negative and never ahead of the committed point they describe.
void CheckStateCounters(const RunState& s) {
  const auto& step_json = s.scheme.at("step");
  const long step = step_json.get<long>();
  const nlohmann::json& t_json = s.scheme.at("t");
  if (!t_json.is_number() || !std::isfinite(t_json.get<double>()) || t_json.get<double>() < 0.0) {
    throw ConfigError(fmt::format("scheme.t = {}: expected a finite time >= 0 s", t_json.dump()));
  }
  if (step < 0) throw ConfigError(fmt::format("scheme.step = {}: a step count is >= 0", step));
  if (s.stage_rows < 0) {
    throw ConfigError(fmt::format("stage_rows = {}: a row count is >= 0", s.stage_rows));
  }
  const bool substeps = s.scheme.value("scheme", std::string()) == "mr-os";
  if (substeps ? s.rows < step + 1 : s.rows != step + 1) {
    throw ConfigError(fmt::format(
        "rows = {} but scheme.step = {}: the committed row of step n is row n{} (rows = step + "
        "1{})", s.rows, step, substeps ? " or later" : "", substeps ? " or more" : ""));
  }
  if (s.statistics.is_object()) {
    for (const char* key : {"steps", "rows", "physical_evaluations"}) {
      const auto it = s.statistics.find(key);
      if (it == s.statistics.end()) continue;
      if (!it->is_number_integer() || it->get<long>() < 0) {
        throw ConfigError(fmt::format("statistics.{} = {}: expected a count >= 0", key,
                                      it->dump()));
      }
    }
    for (const char* key : {"sim_time_s", "wall_time_s", "lab_time_s"}) {
      const auto it = s.statistics.find(key);
      if (it == s.statistics.end()) continue;
      if (!it->is_number() || !std::isfinite(it->get<double>()) || it->get<double>() < 0.0) {
        throw ConfigError(fmt::format("statistics.{} = {}: expected a time >= 0 s", key,
                                      it->dump()));
      }
    }
    // A stop counts the step whose trial failed (session_stop.cc): one ahead at most. (The
    // statistics' rows count the stop's uncommitted rows too, so they are not compared.)
    if (s.statistics.value("steps", 0L) > step + 1) {
      throw ConfigError(fmt::format("statistics.steps = {} is ahead of scheme.step = {}",
                                    s.statistics.value("steps", 0L), step));
    }
  }
  for (const auto& entry : s.substructures) {
    if (!entry.is_object() || !entry.contains("state") || !entry["state"].is_object()) continue;
    const auto& state = entry["state"];
    const auto it = state.find("evaluations");
    if (it != state.end() && (!it->is_number_integer() || it->get<long>() < 0)) {
      throw ConfigError(fmt::format("substructure '{}': evaluations = {}: expected a count >= 0",
                                    entry.value("slot", std::string("?")), it->dump()));
    }
  }
}

}  // namespace

std::string RunStateChecksum(const nlohmann::json& j) {
  if (!j.is_object()) return {};
  nlohmann::json copy = j;
  copy.erase("checksum");
  return io::Sha256Hex(copy.dump());
}

std::string RunStatePath(const std::string& csv_path) { return io::RunStatePath(csv_path); }

nlohmann::json ToJson(const RunState& s) {
  nlohmann::json j = {{"format", kFormat},         {"version", kVersion},
                      {"rows", s.rows},            {"stage_rows", s.stage_rows},
                      {"scheme", s.scheme},        {"substructures", s.substructures},
                      {"statistics", s.statistics}, {"stiffness", s.stiffness},
                      {"row", RowToJson(s.row)},
                      {"journal", {{"rows", s.journal_rows},
                                   {"last_row", s.journal_last_row
                                                    ? RowToJson(*s.journal_last_row)
                                                    : nlohmann::json(nullptr)}}},
                      {"inputs", s.inputs}};
  j["checksum"] = RunStateChecksum(j);
  return j;
}

RunState RunStateFromJson(const nlohmann::json& j, const std::string& where) {
  const auto format = j.is_object() ? j.find("format") : j.end();
  if (!j.is_object() || format == j.end() || !format->is_string() ||
      format->get<std::string>() != kFormat) {
    throw ConfigError(fmt::format("{}: not a hybridtest run state (expected \"format\": \"{}\")",
                                  where, kFormat));
  }
  const auto version = j.find("version");
  if (version == j.end() || !version->is_number_integer() || version->get<long>() != kVersion) {
    throw ConfigError(fmt::format(
        "{}: run state version {}; this hybridtest reads version {} (a run started by an older "
        "hybridtest cannot be verified: finish it with that version, or start it again)",
        where, version == j.end() ? "(none)" : version->dump(), kVersion));
  }
  const auto checksum = j.find("checksum");
  if (checksum == j.end() || !checksum->is_string() ||
      checksum->get<std::string>() != RunStateChecksum(j)) {
    throw ConfigError(fmt::format(
        "{}: the run state's checksum does not match its contents: the file was edited or "
        "damaged, and resume will not trust it. Restore the file the run wrote; a run state is "
        "never edited by hand", where));
  }
  // A count: an integer in JSON (a float such as 1e300 would not fit a long).
  auto count = [](const nlohmann::json& v) {
    if (!v.is_number_integer()) throw ConfigError("a count is not an integer");
    return v.get<long>();
  };
  try {
    RunState s;
    s.rows = count(j.at("rows"));
    s.stage_rows = count(j.at("stage_rows"));
    s.scheme = j.at("scheme");
    if (!s.scheme.is_object() || !s.scheme.contains("step") ||
        !s.scheme["step"].is_number_integer()) {
      throw ConfigError("scheme.step is not an integer");
    }
    s.substructures = j.at("substructures");
    s.statistics = j.at("statistics");
    s.stiffness = j.at("stiffness");
    s.row = RowFromJson(j.at("row"));
    s.journal_rows = count(j.at("journal").at("rows"));
    if (!j.at("journal").at("last_row").is_null()) {
      s.journal_last_row = RowFromJson(j.at("journal").at("last_row"));
    }
    s.inputs = j.at("inputs");
    if (s.rows < 1 || !s.substructures.is_array() || !s.inputs.is_array() || s.row.empty() ||
        s.journal_rows < 0 || s.journal_rows > s.rows ||
        (s.journal_rows > 0) != s.journal_last_row.has_value()) {
      throw ConfigError("inconsistent counts (rows, journal.rows, row)");
    }
    CheckStateCounters(s);
    CheckStateAgreesWithItsRow(s);
    return s;
  } catch (const std::exception& e) {
    throw ConfigError(fmt::format("{}: damaged run state: {}", where, e.what()));
  }
}

JournalRows ReadJournalRows(const std::string& csv_path, const std::vector<long>& indices) {
  std::ifstream in(csv_path, std::ios::binary);
  if (!in) throw IoError(fmt::format("{}: cannot read the journal: {}", csv_path, io::OsError()));
  JournalRows result;
  std::string line;
  long index = -1;  // the header is line −1
  while (std::getline(in, line)) {
    if (in.eof()) break;  // no newline: a partial last line, not a row
    if (index >= 0 && std::find(indices.begin(), indices.end(), index) != indices.end()) {
      std::vector<double> values;
      const char* p = line.c_str();
      const char* end = p + line.size();
      while (p <= end) {
        const char* comma = std::find(p, end, ',');
        values.push_back(std::strtod(std::string(p, comma).c_str(), nullptr));
        p = comma + 1;
      }
      result.rows.emplace(index, std::move(values));
    }
    ++index;
  }
  result.complete = std::max(index, 0L);
  return result;
}

namespace {

// Where a journal row's columns are, from the state: t, x (nx), r (m), then command, position,
// force and lab time of each of `actuators` physical actuators.
struct RowLayout {
  std::size_t nx = 0, m = 0, actuators = 0;
};

RowLayout LayoutOf(const RunState& s) {
  RowLayout layout;
  layout.nx = s.scheme.at("x").size();
  layout.m = s.scheme.at("r").size();
  const std::size_t fixed = 1 + layout.nx + layout.m;
  if (s.row.size() > fixed && (s.row.size() - fixed) % 4 == 0) {
    layout.actuators = (s.row.size() - fixed) / 4;
  }
  return layout;
}

// The journal read once: the rows asked for, and which rows are committed points with a
// specimen sample (Session::FillRow: only a committed row carries the actuators' exchange;
// an intermediate row and an uncommitted one have NaN there).
struct JournalScan {
  JournalRows rows;
  long committed_before = 0;  // committed rows among rows 0..state_rows−1
  long committed_after = 0;   // committed rows from row state_rows on
  long last_committed = -1;   // index of the last committed row
};

JournalScan ScanJournal(const std::string& csv_path, const std::vector<long>& indices,
                        const RowLayout& layout, long state_rows) {
  std::ifstream in(csv_path, std::ios::binary);
  if (!in) throw IoError(fmt::format("{}: cannot read the journal: {}", csv_path, io::OsError()));
  JournalScan scan;
  std::string line;
  long index = -1;  // the header is line −1
  std::vector<double> values;
  while (std::getline(in, line)) {
    if (in.eof()) break;  // no newline: a partial last line, not a row
    if (index >= 0) {
      values.clear();
      const char* p = line.c_str();
      const char* end = p + line.size();
      while (p <= end) {
        const char* comma = std::find(p, end, ',');
        values.push_back(std::strtod(std::string(p, comma).c_str(), nullptr));
        p = comma + 1;
      }
      if (std::find(indices.begin(), indices.end(), index) != indices.end()) {
        scan.rows.rows.emplace(index, values);
      }
      if (layout.actuators > 0 && values.size() == 1 + layout.nx + layout.m + 4 * layout.actuators) {
        bool committed = true;
        for (std::size_t k = 0; k < layout.actuators && committed; ++k) {
          committed = !std::isnan(values[1 + layout.nx + layout.m + 4 * k]);
        }
        if (committed) {
          (index < state_rows ? scan.committed_before : scan.committed_after) += 1;
          scan.last_committed = index;
        }
      }
    }
    ++index;
  }
  scan.rows.complete = std::max(index, 0L);
  return scan;
}

}  // namespace

void VerifyRunStateAgainstJournal(const RunState& state, const std::string& csv_path) {
  const std::string state_path = RunStatePath(csv_path);
  const RowLayout layout = LayoutOf(state);
  const JournalScan scan =
      ScanJournal(csv_path, {state.journal_rows - 1, state.rows - 1, 1}, layout, state.rows);
  const JournalRows& j = scan.rows;
  auto refuse = [&](const std::string& what) {
    throw ConfigError(fmt::format(
        "{}: the run state {} does not belong to this journal: {}. Resume refuses, and nothing "
        "was changed: restore the journal and the state the run wrote together (a journal or a "
        "state copied from another run, edited, or cut cannot be continued)",
        csv_path, state_path, what));
  };
  if (j.complete < state.journal_rows) {
    refuse(fmt::format("the journal has {} rows, but held {} when the state was saved",
                       j.complete, state.journal_rows));
  }
  if (state.journal_last_row) {
    const auto& row = j.rows.at(state.journal_rows - 1);
    if (!SameValues(row, *state.journal_last_row)) {
      refuse(fmt::format("its row {} is {} but was {} when the state was saved",
                         state.journal_rows - 1, Describe(row), Describe(*state.journal_last_row)));
    }
  }
  if (const auto it = j.rows.find(state.rows - 1); it != j.rows.end()) {
    if (!SameValues(it->second, state.row)) {
      refuse(fmt::format("the committed row {} is {} in the journal but {} in the state",
                         state.rows - 1, Describe(it->second), Describe(state.row)));
    }
  } else if (j.complete != state.rows - 1) {
    refuse(fmt::format("the journal has {} rows; the state's committed row is row {}",
                       j.complete, state.rows - 1));
  }
  // A fixed-step Runge-Kutta run (its scheme named after its tableau: not one of the
  // operator-splitting schemes) commits step n at t = n·h exactly (runge_kutta_scheme.cc), h
  // being row 1's t.
  const std::string scheme_name = state.scheme.value("scheme", std::string());
  if (scheme_name != "alpha-os" && scheme_name != "mr-os" &&
      state.scheme.at("step").get<long>() >= 1 && j.rows.count(1) != 0 &&
      !j.rows.at(1).empty()) {
    const double h = j.rows.at(1)[0];
    const long n = state.scheme.at("step").get<long>();
    const double t = state.scheme.at("t").get<double>();
    if (t != static_cast<double>(n) * h) {
      refuse(fmt::format("its step {} and time t = {} s disagree: the run's fixed step is {} s "
                         "(the journal's row 1), so step {} is at t = {} s",
                         n, t, h, n, static_cast<double>(n) * h));
    }
  }
  // The journal is the truth: the state must be the latest. A run with a physical slot saves
  // its state at every committed row, before the row (a real-time run when it stops, at its
  // last committed row): no committed row may follow the state's. An older state would cut
  // those rows and re-run their steps on the specimen.
  const long step = state.scheme.at("step").get<long>();
  auto refuse_older = [&](const std::string& what) {
    throw ConfigError(fmt::format(
        "{}: the run state {} is older than the journal: {}. Resuming from it would cut "
        "committed rows and run their steps again{}. Resume refuses, and nothing was changed "
        "or moved: restore the run state the run wrote last (an older copy of a state, or one "
        "edited and re-checksummed, cannot be continued)",
        csv_path, state_path, what, layout.actuators > 0 ? " on the specimen" : ""));
  };
  if (layout.actuators > 0) {
    if (scan.committed_after > 0) {
      refuse_older(fmt::format(
          "it belongs to committed row {} (step {}, t = {} s), but the journal holds {} "
          "committed row{} after it, the last being row {}",
          state.rows - 1, step, state.row.empty() ? 0.0 : state.row[0], scan.committed_after,
          scan.committed_after == 1 ? "" : "s", scan.last_committed));
    }
    // Every step commits one row with a specimen sample: rows 0..rows−1 hold step + 1 of them
    // (the state's own row counts where a crash lost it).
    const long committed = scan.committed_before + (j.complete == state.rows - 1 ? 1 : 0);
    if (committed != step + 1) {
      refuse(fmt::format("it says step {}, but the journal's rows 0 to {} hold {} committed "
                         "steps' rows (step + 1 = {} expected)",
                         step, state.rows - 1, committed, step + 1));
    }
  } else if (state.scheme.value("scheme", std::string()) != "mr-os") {
    // Numerical: the state is saved every kStateInterval rows (and at the end), so it may be
    // older than the journal by less than two intervals; re-running those steps moves nothing.
    constexpr long kStateInterval = 1000;
    if (j.complete - state.rows >= 2 * kStateInterval) {
      refuse_older(fmt::format("it belongs to row {}, but the journal holds {} rows; a "
                               "numerical run saves its state every {} rows",
                               state.rows - 1, j.complete, kStateInterval));
    }
  }
}

long CutJournalToRows(const std::string& csv_path, long rows) {
  std::ifstream in(csv_path, std::ios::binary);
  if (!in) throw IoError(fmt::format("{}: cannot read the journal: {}", csv_path, io::OsError()));
  // Offset after the header and `rows` complete lines; count the complete lines after it.
  std::string line;
  std::int64_t keep = -1;
  long complete = -1;  // data rows (the header is line 0)
  std::int64_t offset = 0;
  while (std::getline(in, line)) {
    if (in.eof()) break;  // no newline: a partial last line
    offset += static_cast<std::int64_t>(line.size()) + 1;
    ++complete;
    if (complete == rows) keep = offset;
  }
  if (complete <= rows) return 0;
  in.close();
  const int fd = ::open(csv_path.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd >= 0) {
    // Never a live run's journal (run_lock.h): refused if another process writes it.
    try {
      io::LockJournalFile(fd, csv_path);
    } catch (...) {
      ::close(fd);
      throw;
    }
  }
  if (fd < 0 || ::ftruncate(fd, static_cast<off_t>(keep)) != 0 || ::fsync(fd) != 0) {
    const std::string error = io::OsError();
    if (fd >= 0) ::close(fd);
    throw IoError(fmt::format("{}: cannot cut the journal back to its row {}: {}", csv_path,
                              rows - 1, error));
  }
  ::close(fd);
  return complete - rows;
}

void SaveRunState(const std::string& path, const RunState& state) {
  io::WriteFileAtomically(path, ToJson(state).dump() + "\n");
}

RunState LoadRunState(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  struct stat st {};
  if (fd < 0 || ::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode) || st.st_size > (64 << 20)) {
    const std::string error = fd < 0 ? io::OsError() : "not a regular file of at most 64 MiB";
    if (fd >= 0) ::close(fd);
    throw ConfigError(fmt::format("{}: cannot read the run state: {}; a run writes it beside its "
                                  "journal", path, error));
  }
  std::string text(static_cast<std::size_t>(st.st_size), '\0');
  const ssize_t n = ::pread(fd, text.data(), text.size(), 0);
  ::close(fd);
  if (n != static_cast<ssize_t>(text.size())) {
    throw ConfigError(fmt::format("{}: cannot read the run state: {}", path, io::OsError()));
  }
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw ConfigError(fmt::format("{}: the run state is not valid JSON (truncated or damaged): "
                                  "{}; restore the file the run wrote", path, e.what()));
  }
  return RunStateFromJson(j, path);
}

}  // namespace hybridtest::runner
