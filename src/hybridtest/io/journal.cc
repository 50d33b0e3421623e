#include "hybridtest/io/journal.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <set>

#include "hybridtest/common/error.h"
#include "hybridtest/common/version.h"
#include "hybridtest/io/atomic_file.h"
#include "hybridtest/io/csv.h"
#include "hybridtest/io/run_lock.h"
#include "hybridtest/io/utc_time.h"

namespace hybridtest::io {
namespace {

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

std::string StagedPath(const std::string& path) { return path + ".partial"; }

std::string StagesPath(const std::string& csv_path) {
  const std::filesystem::path p(csv_path);
  return (p.parent_path() / (p.stem().string() + ".stages.csv")).string();
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

  // The staged CSV is opened and locked first (never truncated before it is locked: another
  // writer's staged journal is left alone), then the staged sidecar is written, so that a
  // CSV is never published without its metadata.
  const std::string staged = StagedPath(csv_path_);
  fd_ = ::open(staged.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
  if (fd_ < 0) {
    throw IoError(fmt::format("{}: cannot create the journal: {}; check that the directory "
                              "exists and is writable",
                              staged, OsError()));
  }
  try {
    // The writer's lock, held for the journal's life (run_lock.h): it moves with the file
    // when the staged journal is published.
    LockJournalFile(fd_, staged);
  } catch (...) {
    ::close(fd_);
    fd_ = -1;
    throw;
  }
  if (::ftruncate(fd_, 0) != 0) {
    const std::string error = OsError();
    Discard();
    throw IoError(fmt::format("{}: cannot empty the staged journal: {}", staged, error));
  }
  try {
    WriteSidecar(/*reserve_next=*/false);
  } catch (...) {
    Discard();
    throw;
  }
  if (policy_ == SyncPolicy::kBuffered) pending_.reserve(kJournalBlockBytes + 64 * 1024);
  last_write_ = last_sync_ = Now();
  std::vector<std::string> names;
  for (const auto& channel : channels_) names.push_back(channel.name);
  try {
    WriteRow(FormatCsvHeader(names));
  } catch (...) {
    Discard();
    throw;
  }
}

Journal::~Journal() {
  if (fd_ < 0) return;
  if (!published_) {
    Discard();
    return;
  }
  try {
    WritePending();
  } catch (...) {
    // A destructor never throws; the rows that could not be written are lost either way.
  }
  ::fsync(fd_);
  ::close(fd_);
  fd_ = -1;
  if (!finished_ && status_is_running_) {
    // Closed without Finish: an exception unwound the run. Say so in the sidecar.
    try {
      sidecar_["status"] = "aborted: the journal was closed without Finish()";
      sidecar_["rows"] = rows_;
      WriteSidecar(/*reserve_next=*/false);
    } catch (...) {
      // A destructor never throws; the CSV, the record of truth, is already synced.
    }
  }
  ::unlink(AtomicTempPath(SidecarPath(csv_path_)).c_str());
}

void Journal::WriteRow(const std::string& line) {
  std::size_t written = 0;
  while (written < line.size()) {
    const ssize_t n = ::pwrite(fd_, line.data() + written, line.size() - written,
                               static_cast<off_t>(size_ + static_cast<std::int64_t>(written)));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const std::string error = n == 0 ? "no byte written" : OsError();
      // Cut the partial line: the file ends with its last whole row.
      const bool cut = ::ftruncate(fd_, static_cast<off_t>(size_)) == 0;
      throw IoError(fmt::format(
          "{}: cannot write {}: {}; check free disk space{}",
          published_ ? csv_path_ : StagedPath(csv_path_),
          rows_ == 0 && size_ == 0 ? std::string("the header line") : fmt::format("row {}", rows_ + 1),
          error, cut ? "" : " (and the partial line could not be cut: " + OsError() + ")"));
    }
    written += static_cast<std::size_t>(n);
  }
  size_ += static_cast<std::int64_t>(line.size());
}

void Journal::SyncCsv(long row) {
  if (::fsync(fd_) != 0) {
    throw IoError(fmt::format("{}: cannot sync row {} to disk: {}", csv_path_, row, OsError()));
  }
  last_sync_ = Now();
  unsynced_ = false;
}

void Journal::WriteSidecar(bool reserve_next) {
  const std::string path = published_ ? SidecarPath(csv_path_) : StagedPath(SidecarPath(csv_path_));
  WriteFileAtomically(path, sidecar_.dump(2) + "\n");
  if (reserve_next) ReserveNextSidecar();
}

void Journal::ReserveNextSidecar() {
  // Twice its size now, at least 64 KiB: room for statistics, a stop's history, resumes.
  const auto size = static_cast<std::int64_t>(sidecar_.dump(2).size());
  ReserveSpace(SidecarPath(csv_path_), std::max<std::int64_t>(2 * size, 64 * 1024));
}

void Journal::Publish() {
  const std::string sidecar = SidecarPath(csv_path_);
  // The row and the header reach the disk before the new run takes the name.
  SyncCsv(1);
  // An older sidecar goes first: a crash below leaves a CSV without sidecar, never a CSV
  // with the metadata of another run.
  if (::unlink(sidecar.c_str()) != 0 && errno != ENOENT) {
    throw IoError(fmt::format("{}: cannot remove the sidecar of the run being replaced: {}",
                              sidecar, OsError()));
  }
  if (::rename(StagedPath(csv_path_).c_str(), csv_path_.c_str()) != 0) {
    throw IoError(fmt::format("{}: cannot rename {} to it: {}", csv_path_,
                              StagedPath(csv_path_), OsError()));
  }
  published_ = true;
  if (::rename(StagedPath(sidecar).c_str(), sidecar.c_str()) != 0) {
    throw IoError(fmt::format("{}: cannot rename {} to it: {}", sidecar, StagedPath(sidecar),
                              OsError()));
  }
  SyncDirectory(ParentDirectory(csv_path_));
  ReserveNextSidecar();
}

void Journal::Discard() noexcept {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  const std::string sidecar = SidecarPath(csv_path_);
  ::unlink(StagedPath(csv_path_).c_str());
  ::unlink(StagedPath(sidecar).c_str());
  ::unlink(AtomicTempPath(StagedPath(sidecar)).c_str());
}

void Journal::Append(std::span<const double> row, bool durable) {
  if (row.size() != channels_.size()) {
    throw IoError(fmt::format("{}: row {} has {} values, expected {} (one per channel)",
                              csv_path_, rows_ + 1, row.size(), channels_.size()));
  }
  if (finished_ || fd_ < 0) {
    throw IoError(fmt::format("{}: Append() after Finish(): the journal is closed", csv_path_));
  }
  if (policy_ == SyncPolicy::kBuffered && published_ && status_is_running_) {
    // Numerical runs: rows are collected and written in blocks, synced at a bounded interval.
    AppendCsvRow(row, pending_);
    last_row_.assign(row.begin(), row.end());  // no allocation once sized
    ++rows_;
    if (pending_.size() >= kJournalBlockBytes) {
      WritePending();
    } else if ((rows_ & 63) == 0) {
      // The clock is read every 64 rows only: a numerical row costs well under a microsecond.
      const double now = Now();
      if (now - last_write_ >= kJournalWriteInterval) WritePending();
    }
    if (unsynced_ && last_write_ - last_sync_ >= kJournalSyncInterval) SyncCsv(written_rows_);
    return;
  }
  WritePending();
  line_.clear();
  AppendCsvRow(row, line_);
  // One pwrite hands the row to the kernel: from here on a crash of the process loses nothing.
  WriteRow(line_);
  last_row_.assign(row.begin(), row.end());
  ++rows_;
  written_rows_ = rows_;
  unsynced_ = true;
  if (!published_) {
    Publish();
    return;
  }
  if (!status_is_running_) {
    // A reopened journal runs again: its sidecar says so from its first new row on.
    sidecar_["status"] = "running";
    sidecar_.erase("finish_time");
    WriteSidecar(/*reserve_next=*/true);
    status_is_running_ = true;
  }
  // fsync puts it on the disk: from here on a power cut loses nothing either.
  if ((policy_ == SyncPolicy::kEveryRow && durable) ||
      (policy_ == SyncPolicy::kBatched && rows_ % batch_rows_ == 0)) {
    SyncCsv(rows_);
  }
}

void Journal::WritePending() {
  if (pending_.empty()) return;
  const long first = written_rows_ + 1;
  const long last = rows_;
  try {
    WriteRow(pending_);
  } catch (const IoError& e) {
    // The file was cut back to its last whole written row; the rows held here are lost.
    pending_.clear();
    rows_ = written_rows_;
    throw IoError(fmt::format("{} (rows {} to {} were not written)", e.what(), first,
                              last));
  }
  pending_.clear();
  written_rows_ = rows_;
  last_write_ = Now();
  unsynced_ = true;
}

void Journal::Flush(bool sync) {
  if (fd_ < 0) return;
  WritePending();
  if (sync && unsynced_ && published_) SyncCsv(written_rows_);
}

double Journal::Now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

void Journal::Finish(const nlohmann::json& statistics, const std::string& status) {
  if (fd_ < 0 && !published_) return;  // already discarded
  if (!published_) {
    // No row was ever committed: the run leaves nothing behind.
    finished_ = true;
    Discard();
    return;
  }
  std::string csv_error;
  if (fd_ >= 0) {
    try {
      WritePending();
    } catch (const IoError& e) {
      csv_error = e.what();
    }
  }
  if (fd_ >= 0 && ::fsync(fd_) != 0 && csv_error.empty()) {
    csv_error = fmt::format("{}: cannot sync the journal to disk: {}", csv_path_, OsError());
  }
  finished_ = true;
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  sidecar_["statistics"] = statistics;
  sidecar_["status"] = status;
  sidecar_["rows"] = rows_;
  sidecar_["finish_time"] = UtcNowIso8601();
  // Into the reserved blocks: this works on a full disk too.
  WriteSidecar(/*reserve_next=*/false);
  if (!csv_error.empty()) throw IoError(csv_error);
}

void Journal::SetSidecarEntry(const std::string& key, nlohmann::json value) {
  if (!published_) {
    throw IoError(fmt::format("{}: SetSidecarEntry('{}') before the first row: the journal is "
                              "not published yet",
                              csv_path_, key));
  }
  sidecar_[key] = std::move(value);
  WriteSidecar(/*reserve_next=*/!finished_);
}

}  // namespace hybridtest::io
