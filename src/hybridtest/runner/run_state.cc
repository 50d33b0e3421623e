// See run_state.h.
#include "hybridtest/runner/run_state.h"

#include <fmt/core.h>

#include <fcntl.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "hybridtest/common/error.h"
#include "hybridtest/io/atomic_file.h"

namespace hybridtest::runner {

namespace {
constexpr const char* kFormat = "hybridtest-run-state";
constexpr int kVersion = 1;
}  // namespace

std::string RunStatePath(const std::string& csv_path) {
  const std::filesystem::path p(csv_path);
  return (p.parent_path() / (p.stem().string() + ".state.json")).string();
}

nlohmann::json ToJson(const RunState& s) {
  return {{"format", kFormat},         {"version", kVersion},
          {"rows", s.rows},            {"stage_rows", s.stage_rows},
          {"scheme", s.scheme},        {"substructures", s.substructures},
          {"statistics", s.statistics}, {"stiffness", s.stiffness}};
}

RunState RunStateFromJson(const nlohmann::json& j, const std::string& where) {
  if (!j.is_object() || j.value("format", "") != kFormat) {
    throw IoError(fmt::format("{}: not a hybridtest run state (expected \"format\": \"{}\")",
                              where, kFormat));
  }
  if (j.value("version", 0) != kVersion) {
    throw IoError(fmt::format("{}: run state version {}; this hybridtest reads version {}",
                              where, j.value("version", 0), kVersion));
  }
  try {
    RunState s;
    s.rows = j.at("rows").get<long>();
    s.stage_rows = j.at("stage_rows").get<long>();
    s.scheme = j.at("scheme");
    s.substructures = j.at("substructures");
    s.statistics = j.at("statistics");
    s.stiffness = j.at("stiffness");
    if (s.rows < 1 || !s.substructures.is_array()) throw IoError("rows < 1 or no slots");
    return s;
  } catch (const std::exception& e) {
    throw IoError(fmt::format("{}: damaged run state: {}", where, e.what()));
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
  const int fd = ::open(csv_path.c_str(), O_WRONLY);
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
  std::ifstream in(path);
  if (!in) {
    throw IoError(fmt::format("{}: cannot read the run state: {}; a run writes it beside its "
                              "journal (hybridtest 0.x runs before resume existed have none)",
                              path, io::OsError()));
  }
  std::stringstream text;
  text << in.rdbuf();
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text.str());
  } catch (const nlohmann::json::exception& e) {
    throw IoError(fmt::format("{}: the run state is not valid JSON: {}", path, e.what()));
  }
  return RunStateFromJson(j, path);
}

}  // namespace hybridtest::runner
