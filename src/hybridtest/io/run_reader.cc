#include "hybridtest/io/run_reader.h"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "hybridtest/common/error.h"
#include "hybridtest/common/input_file.h"
#include "hybridtest/io/csv.h"

namespace hybridtest::io {
namespace {

// LoadRun's errors are IoErrors (the CLI turns them into exit 2 where a user named the file).
void RequireRunFile(const std::string& path, std::string_view expected) {
  try {
    RequireRegularFile(path, "", expected);
  } catch (const ConfigError& e) {
    throw IoError(e.what());
  }
}

std::string ReadWholeFile(const std::string& path) {
  RequireRunFile(path, "run journal (the .csv file written by 'hybridtest run')");
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw IoError(fmt::format("{}: cannot open the run for reading: {}; check the path (a run "
                              "is the .csv file written by 'hybridtest simulate' or 'run')",
                              path, std::strerror(errno)));
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw IoError(fmt::format("{}: read error: {}", path, std::strerror(errno)));
  return std::move(text).str();
}

std::string ListChannels(const std::vector<Channel>& channels) {
  std::string list;
  for (const auto& channel : channels) {
    if (!list.empty()) list += ", ";
    list += channel.name;
  }
  return list;
}

// Fills unit and description of each channel from the sidecar when its channel list matches
// the CSV header, else from the names (with a warning if a sidecar exists but disagrees).
void AttachChannelInfo(RunData& run) {
  const nlohmann::json* listed = nullptr;
  if (run.metadata.is_object() && run.metadata.contains("channels") &&
      run.metadata["channels"].is_array()) {
    listed = &run.metadata["channels"];
  }
  bool matches = listed != nullptr && listed->size() == run.channels.size();
  for (std::size_t i = 0; matches && i < run.channels.size(); ++i) {
    const auto& entry = (*listed)[i];
    matches = entry.is_object() && entry.value("name", std::string()) == run.channels[i].name;
  }
  if (run.metadata.is_object() && !matches) {
    run.warnings.push_back(fmt::format(
        "{}: the sidecar's channel list does not match the CSV header; units inferred from "
        "the channel names",
        SidecarPath(run.csv_path)));
  }
  for (std::size_t i = 0; i < run.channels.size(); ++i) {
    Channel& channel = run.channels[i];
    if (matches) {
      channel.unit = (*listed)[i].value("unit", InferChannelUnit(channel.name));
      channel.description =
          (*listed)[i].value("description", InferChannelDescription(channel.name));
    } else {
      channel.unit = InferChannelUnit(channel.name);
      channel.description = InferChannelDescription(channel.name);
    }
  }
}

void LoadSidecar(RunData& run) {
  const std::string path = SidecarPath(run.csv_path);
  if (RegularFileProblem(path) == "no such file") return;  // no sidecar: metadata stays null
  RequireRunFile(path, "run sidecar (.meta.json)");  // a FIFO would block for ever
  std::ifstream in(path, std::ios::binary);
  if (!in) return;  // no sidecar: metadata stays null
  try {
    run.metadata = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw IoError(fmt::format("{}: the run's sidecar is not valid JSON ({}); repair it or move "
                              "it away to read the CSV alone with inferred units",
                              path, e.what()));
  }
}

}  // namespace

int RunData::Column(std::string_view name) const {
  for (std::size_t i = 0; i < channels.size(); ++i) {
    if (channels[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

namespace {
int RequireColumn(const RunData& run, std::string_view name) {
  const int column = run.Column(name);
  if (column < 0) {
    throw IoError(fmt::format("{}: no channel '{}' in this run; available channels: {}",
                              run.csv_path, name, ListChannels(run.channels)));
  }
  return column;
}
}  // namespace

Eigen::VectorXd RunData::Get(std::string_view name) const {
  return values.col(RequireColumn(*this, name));
}

std::string RunData::Unit(std::string_view name) const {
  return channels[static_cast<std::size_t>(RequireColumn(*this, name))].unit;
}

std::string RunData::Description(std::string_view name) const {
  return channels[static_cast<std::size_t>(RequireColumn(*this, name))].description;
}

RunData LoadRun(const std::string& csv_path) {
  RunData run;
  run.csv_path = csv_path;
  const std::string text = ReadWholeFile(csv_path);

  // Header line.
  const std::size_t header_end = text.find('\n');
  if (text.empty() || header_end == std::string::npos) {
    throw IoError(fmt::format("{}:1: expected a header line of channel names ending in a "
                              "newline, got {}; the run was interrupted before its first row "
                              "or this is not a hybridtest run",
                              csv_path, text.empty() ? "an empty file" : "an unterminated line"));
  }
  for (const auto name : SplitCsvLine(std::string_view(text).substr(0, header_end))) {
    if (!IsValidChannelName(name)) {
      throw IoError(fmt::format("{}:1: expected channel names (no blanks, quotes or empty "
                                "names), got '{}'",
                                csv_path, name));
    }
    run.channels.push_back(Channel{std::string(name), "", ""});
  }
  const std::size_t num_channels = run.channels.size();

  // Data lines: collected row-major, then mapped into the matrix.
  std::vector<double> data;
  long rows = 0;
  std::size_t pos = header_end + 1;
  long line_number = 1;
  while (pos < text.size()) {
    ++line_number;
    const std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) {
      run.warnings.push_back(fmt::format(
          "{}:{}: dropped a truncated last line (no newline: the writer stopped mid-row)",
          csv_path, line_number));
      break;
    }
    const auto fields = SplitCsvLine(std::string_view(text).substr(pos, end - pos));
    if (fields.size() != num_channels) {
      throw IoError(fmt::format("{}:{}: expected {} comma-separated values (one per channel), "
                                "got {}; the file is damaged or was edited by hand",
                                csv_path, line_number, num_channels, fields.size()));
    }
    for (std::size_t i = 0; i < num_channels; ++i) {
      const auto value = ParseCsvNumber(fields[i]);
      if (!value) {
        throw IoError(fmt::format("{}:{}: channel '{}': expected a number, got '{}'", csv_path,
                                  line_number, run.channels[i].name, fields[i]));
      }
      data.push_back(*value);
    }
    ++rows;
    pos = end + 1;
  }
  run.values = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic,
                                              Eigen::RowMajor>>(
      data.data(), rows, static_cast<Eigen::Index>(num_channels));

  LoadSidecar(run);
  AttachChannelInfo(run);
  return run;
}

}  // namespace hybridtest::io
