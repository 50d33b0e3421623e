#pragma once
// Helpers for the campaign tests: the summary as rows, the metric columns, the sidecar, the
// case results on disk, and whether mpirun and an MPI-built hybridtest are here.
#include <nlohmann/json.hpp>

#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "support/run_command.h"
#include "support/temp_dir.h"

namespace hybridtest::campaign_test {

namespace fs = std::filesystem;

inline const std::string kBinary = HYBRIDTEST_BINARY;
inline const std::string kSource = HYBRIDTEST_SOURCE_DIR;
inline const std::string kRotorWind = kSource + "/examples/campaigns/rotor-wind.yaml";

using Row = std::map<std::string, std::string>;

// summary.csv as rows keyed by column (RFC 4180 quotes understood).
inline std::vector<Row> ReadSummary(const fs::path& path) {
  const std::string text = test_support::ReadText(path);
  std::vector<std::vector<std::string>> records{{}};
  std::string field;
  bool quoted = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        field += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      records.back().push_back(field);
      field.clear();
    } else if (c == '\n') {
      records.back().push_back(field);
      field.clear();
      records.emplace_back();
    } else {
      field += c;
    }
  }
  records.pop_back();  // after the last '\n'
  std::vector<Row> rows;
  if (records.empty()) return rows;
  for (std::size_t r = 1; r < records.size(); ++r) {
    Row row;
    for (std::size_t k = 0; k < records[0].size() && k < records[r].size(); ++k) {
      row[records[0][k]] = records[r][k];
    }
    rows.push_back(row);
  }
  return rows;
}

// Every column but those that depend on the machine (duration, worker).
inline std::vector<Row> Comparable(std::vector<Row> rows) {
  for (auto& row : rows) {
    row.erase("duration_s");
    row.erase("worker");
  }
  return rows;
}

inline nlohmann::json Sidecar(const fs::path& dir) {
  return nlohmann::json::parse(test_support::ReadText(dir / "campaign.json"));
}

// The ids the last invocation ran.
inline std::set<std::string> RanLast(const fs::path& dir) {
  std::set<std::string> ids;
  const nlohmann::json sidecar = Sidecar(dir);
  for (const auto& id : sidecar["invocations"].back()["ran"]) ids.insert(id.get<std::string>());
  return ids;
}

// The ids with a case.json, and their texts.
inline std::map<std::string, std::string> DoneCases(const fs::path& dir) {
  std::map<std::string, std::string> done;
  if (!fs::exists(dir / "cases")) return done;
  for (const auto& entry : fs::directory_iterator(dir / "cases")) {
    const fs::path record = entry.path() / "case.json";
    if (fs::exists(record)) {
      done[entry.path().filename().string()] = test_support::ReadText(record);
    }
  }
  return done;
}

inline std::string Campaign(const fs::path& campaign, const fs::path& out,
                            const std::string& extra = "") {
  return kBinary + " campaign " + campaign.string() + " --out " + out.string() + " " + extra;
}

// "mpirun ... -n N --oversubscribe" for Open MPI, or "" when mpirun or an MPI-built
// hybridtest is missing (`why` says which).
inline std::string Mpirun(int ranks, std::string* why) {
  const auto [found, path] = testing::RunCommand("sh -c 'command -v mpirun'");
  if (found != 0 || path.empty()) {
    *why = "mpirun is not installed (Debian: openmpi-bin)";
    return "";
  }
  const auto [help_status, help] = testing::RunCommand(kBinary + " campaign --help");
  if (help.find("MPI: built with") == std::string::npos) {
    *why = "hybridtest was built without MPI (Debian: libopenmpi-dev)";
    return "";
  }
  std::string mpirun = path.substr(0, path.find('\n'));
  const auto [version_status, version] = testing::RunCommand(mpirun + " --version");
  // Open MPI refuses to run as root without this; it is harmless otherwise.
  if (version.find("Open MPI") != std::string::npos) mpirun += " --allow-run-as-root";
  return mpirun + " -n " + std::to_string(ranks) + " --oversubscribe";
}

// A small campaign of the paper's rotor in `dir`: `grid` is the grid's YAML mapping.
inline fs::path WriteRotorCampaign(const fs::path& dir, const std::string& grid,
                                   double duration) {
  const fs::path file = dir / "campaign.yaml";
  test_support::WriteText(
      file, "base: " + kSource + "/examples/rotor/numerical.yaml\ncommand: simulate\n"
            "set: {duration: " + std::to_string(duration) + "}\ngrid: " + grid +
            "\nmetrics: [max_abs(q1), final(u4)]\nfigures: false\n");
  return file;
}

}  // namespace hybridtest::campaign_test
