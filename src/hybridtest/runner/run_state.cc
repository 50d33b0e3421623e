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
#include "hybridtest/runner/run_state_rows.h"

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
  // The constraint forces end the row; they are derived from the point, not part of it.
  if (s.constraint_forces < 0 ||
      s.row.size() != expected.size() + static_cast<std::size_t>(s.constraint_forces)) {
    throw ConfigError(fmt::format("its row has {} values; its committed point has {} and {} "
                                  "constraint forces", s.row.size(), expected.size(),
                                  s.constraint_forces));
  }
  const std::vector<double> point(s.row.begin(),
                                  s.row.begin() + static_cast<std::ptrdiff_t>(expected.size()));
  if (!SameJournalValues(expected, point)) {
    throw ConfigError(fmt::format("its committed point ({}) is not its row ({}): the parts of the "
                                  "state disagree", DescribeRow(expected), DescribeRow(s.row)));
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
  if (s.constraint_forces > 0) j["constraint_forces"] = s.constraint_forces;
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
    if (j.contains("constraint_forces")) s.constraint_forces = count(j.at("constraint_forces"));
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
