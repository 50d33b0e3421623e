#include "hybridtest/io/journal.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <set>

#include "hybridtest/common/error.h"
#include "hybridtest/common/version.h"
#include "hybridtest/io/csv.h"

namespace hybridtest::io {
namespace {

std::string OsError() { return std::strerror(errno); }

std::string UtcNowIso8601() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char buffer[32];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return buffer;
}

std::string ParentDirectory(const std::string& path) {
  const auto parent = std::filesystem::path(path).parent_path();
  return parent.empty() ? "." : parent.string();
}

// Makes a rename or a file creation in `directory` durable. Best effort: some file systems
// cannot sync a directory, and the data themselves are already synced.
void SyncDirectory(const std::string& directory) {
  const int fd = ::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

// Writes `text` to `path` atomically: a temporary file beside it, fsync, rename over `path`.
void WriteFileAtomically(const std::string& path, const std::string& text) {
  const std::string temp = path + ".tmp";
  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    throw IoError(fmt::format("{}: cannot create the sidecar's temporary file: {}; check that "
                              "the directory exists and is writable",
                              temp, OsError()));
  }
  std::size_t written = 0;
  while (written < text.size()) {
    const ssize_t n = ::write(fd, text.data() + written, text.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const std::string error = OsError();
      ::close(fd);
      ::unlink(temp.c_str());
      throw IoError(fmt::format("{}: cannot write the sidecar: {}; check free disk space",
                                temp, error));
    }
    written += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0 || ::close(fd) != 0) {
    const std::string error = OsError();
    ::unlink(temp.c_str());
    throw IoError(fmt::format("{}: cannot sync the sidecar to disk: {}", temp, error));
  }
  if (::rename(temp.c_str(), path.c_str()) != 0) {
    const std::string error = OsError();
    ::unlink(temp.c_str());
    throw IoError(fmt::format("{}: cannot rename {} over it: {}", path, temp, error));
  }
  SyncDirectory(ParentDirectory(path));
}

void ValidateChannels(const std::string& csv_path, const std::vector<Channel>& channels) {
  if (channels.empty()) {
    throw IoError(fmt::format("{}: a journal needs at least one channel, got none", csv_path));
  }
  std::set<std::string> seen;
  for (const auto& channel : channels) {
    if (!IsValidChannelName(channel.name)) {
      throw IoError(fmt::format("{}: invalid channel name '{}': expected a non-empty name "
                                "without commas, quotes or blanks",
                                csv_path, channel.name));
    }
    if (!seen.insert(channel.name).second) {
      throw IoError(fmt::format("{}: channel '{}' appears twice; channel names must be unique",
                                csv_path, channel.name));
    }
  }
}

}  // namespace

std::string SidecarPath(const std::string& csv_path) {
  return std::filesystem::path(csv_path).replace_extension(".meta.json").string();
}

Journal::Journal(std::string csv_path, std::vector<Channel> channels, JournalMetadata metadata,
                 SyncPolicy policy, int batch_rows)
    : csv_path_(std::move(csv_path)),
      channels_(std::move(channels)),
      policy_(policy),
      batch_rows_(batch_rows) {
  ValidateChannels(csv_path_, channels_);
  if (batch_rows_ < 1) {
    throw IoError(fmt::format("{}: batch_rows = {}: expected a positive number of rows between "
                              "fsyncs",
                              csv_path_, batch_rows_));
  }

  // Sidecar first, so that a CSV never exists without its metadata.
  nlohmann::json channel_list = nlohmann::json::array();
  for (const auto& channel : channels_) {
    channel_list.push_back(
        {{"name", channel.name}, {"unit", channel.unit}, {"description", channel.description}});
  }
  sidecar_ = {{"format", "hybridtest-journal/1"},
              {"software_version", kVersion},
              {"start_time", UtcNowIso8601()},
              {"command", metadata.command},
              {"config_path", metadata.config_path},
              {"config", metadata.config_text},
              {"model", metadata.model},
              {"substructures", metadata.substructures},
              {"extra", metadata.extra},
              {"channels", channel_list},
              {"status", "running"}};
  WriteFileAtomically(SidecarPath(csv_path_), sidecar_.dump(2) + "\n");

  file_ = std::fopen(csv_path_.c_str(), "we");
  if (file_ == nullptr) {
    throw IoError(fmt::format("{}: cannot create the journal: {}; check that the directory "
                              "exists and is writable",
                              csv_path_, OsError()));
  }
  std::vector<std::string> names;
  for (const auto& channel : channels_) names.push_back(channel.name);
  const std::string header = FormatCsvHeader(names);
  if (std::fwrite(header.data(), 1, header.size(), file_) != header.size() ||
      std::fflush(file_) != 0 || ::fsync(::fileno(file_)) != 0) {
    const std::string error = OsError();
    std::fclose(file_);
    file_ = nullptr;
    throw IoError(fmt::format("{}: cannot write the header line: {}", csv_path_, error));
  }
  SyncDirectory(ParentDirectory(csv_path_));
}

Journal::~Journal() {
  if (file_ == nullptr) return;
  std::fflush(file_);
  ::fsync(::fileno(file_));
  std::fclose(file_);
  file_ = nullptr;
  if (!finished_) {
    // Closed without Finish: an exception unwound the run. Say so in the sidecar.
    try {
      sidecar_["status"] = "aborted: the journal was closed without Finish()";
      sidecar_["rows"] = rows_;
      WriteFileAtomically(SidecarPath(csv_path_), sidecar_.dump(2) + "\n");
    } catch (...) {
      // A destructor never throws; the CSV, the record of truth, is already synced.
    }
  }
}

void Journal::Append(std::span<const double> row, bool durable) {
  if (row.size() != channels_.size()) {
    throw IoError(fmt::format("{}: row {} has {} values, expected {} (one per channel)",
                              csv_path_, rows_ + 1, row.size(), channels_.size()));
  }
  if (finished_) {
    throw IoError(fmt::format("{}: Append() after Finish(): the journal is closed", csv_path_));
  }
  line_.clear();
  AppendCsvRow(row, line_);
  // fflush hands the row to the kernel: from here on a crash of the process loses nothing.
  if (std::fwrite(line_.data(), 1, line_.size(), file_) != line_.size() ||
      std::fflush(file_) != 0) {
    throw IoError(fmt::format("{}: cannot append row {}: {}; check free disk space", csv_path_,
                              rows_ + 1, OsError()));
  }
  ++rows_;
  // fsync puts it on the disk: from here on a power cut loses nothing either.
  if ((policy_ == SyncPolicy::kEveryRow && durable) || rows_ % batch_rows_ == 0) {
    if (::fsync(::fileno(file_)) != 0) {
      throw IoError(fmt::format("{}: cannot sync row {} to disk: {}", csv_path_, rows_,
                                OsError()));
    }
  }
}

void Journal::Finish(const nlohmann::json& statistics, const std::string& status) {
  if (std::fflush(file_) != 0 || ::fsync(::fileno(file_)) != 0) {
    throw IoError(fmt::format("{}: cannot sync the journal to disk: {}", csv_path_, OsError()));
  }
  finished_ = true;
  sidecar_["statistics"] = statistics;
  sidecar_["status"] = status;
  sidecar_["rows"] = rows_;
  sidecar_["finish_time"] = UtcNowIso8601();
  WriteFileAtomically(SidecarPath(csv_path_), sidecar_.dump(2) + "\n");
}

}  // namespace hybridtest::io
