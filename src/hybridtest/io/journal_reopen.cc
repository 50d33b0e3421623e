// Reopening a journal to append to it (resume), and reading a sidecar back. See journal.h.
#include <fcntl.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

#include "hybridtest/common/error.h"
#include "hybridtest/io/atomic_file.h"
#include "hybridtest/io/csv.h"
#include "hybridtest/io/journal.h"
#include "hybridtest/io/run_lock.h"

namespace hybridtest::io {
namespace {

// Where the lines of a CSV file end.
struct LineScan {
  std::string header;          // the first line, without '\n'
  long newlines = 0;           // complete lines, header included
  std::int64_t last_end = -1;  // offset of the last '\n' [B]
  std::int64_t prev_end = -1;  // offset of the '\n' before it [B]
  std::int64_t size = 0;       // file size [B]
};

LineScan ScanLines(int fd, const std::string& path) {
  LineScan scan;
  std::string chunk(64 * 1024, '\0');
  bool in_header = true;
  for (;;) {
    const ssize_t n = ::pread(fd, chunk.data(), chunk.size(), static_cast<off_t>(scan.size));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw IoError(fmt::format("{}: cannot read the journal: {}", path, OsError()));
    if (n == 0) return scan;
    for (ssize_t i = 0; i < n; ++i) {
      if (chunk[static_cast<std::size_t>(i)] != '\n') continue;
      if (in_header) scan.header.append(chunk.data(), static_cast<std::size_t>(i));
      in_header = false;
      ++scan.newlines;
      scan.prev_end = scan.last_end;
      scan.last_end = scan.size + i;
    }
    if (in_header) scan.header.append(chunk.data(), static_cast<std::size_t>(n));
    scan.size += n;
  }
}

std::vector<Channel> ChannelsOf(const nlohmann::json& sidecar, const std::string& where) {
  std::vector<Channel> channels;
  try {
    for (const auto& c : sidecar.at("channels")) {
      channels.push_back({c.at("name").get<std::string>(), c.value("unit", ""),
                          c.value("description", "")});
    }
  } catch (const nlohmann::json::exception& e) {
    throw IoError(fmt::format("{}: `channels` is not a list of {{name, unit, description}}: {}",
                              where, e.what()));
  }
  return channels;
}

}  // namespace

nlohmann::json ReadSidecar(const std::string& csv_path) {
  const std::string path = SidecarPath(csv_path);
  std::ifstream in(path);
  if (!in) {
    throw IoError(fmt::format("{}: cannot read the sidecar of {}: {}; a run written by "
                              "hybridtest has one beside its CSV",
                              path, csv_path, OsError()));
  }
  std::stringstream text;
  text << in.rdbuf();
  try {
    return nlohmann::json::parse(text.str());
  } catch (const nlohmann::json::exception& e) {
    throw IoError(fmt::format("{}: not valid JSON: {}", path, e.what()));
  }
}

Journal::Journal(ReopenForAppend, std::string csv_path, SyncPolicy policy, int batch_rows)
    : csv_path_(std::move(csv_path)), policy_(policy), batch_rows_(batch_rows) {
  const std::string sidecar_path = SidecarPath(csv_path_);
  sidecar_ = ReadSidecar(csv_path_);
  if (sidecar_.value("format", "") != "hybridtest-journal/1") {
    throw IoError(fmt::format("{}: format = {}: expected \"hybridtest-journal/1\"",
                              sidecar_path, sidecar_.value("format", nlohmann::json()).dump()));
  }
  channels_ = ChannelsOf(sidecar_, sidecar_path);
  if (batch_rows_ < 1) {
    throw IoError(fmt::format("{}: batch_rows = {}: expected a positive number of rows between "
                              "fsyncs",
                              csv_path_, batch_rows_));
  }

  fd_ = ::open(csv_path_.c_str(), O_RDWR | O_CLOEXEC);
  if (fd_ < 0) {
    throw IoError(fmt::format("{}: cannot open the journal to append to it: {}", csv_path_,
                              OsError()));
  }
  // Everything below closes fd_ on failure: the destructor does not run for a constructor
  // that throws.
  try {
    // The writer's lock (run_lock.h): a live run's journal is never cut or appended to by a
    // second process, even if the run's lock file was removed.
    LockJournalFile(fd_, csv_path_);
    const LineScan scan = ScanLines(fd_, csv_path_);
    if (scan.newlines == 0) {
      throw IoError(fmt::format("{}:1: the header line is incomplete (no '\\n'); the run "
                                "never wrote a row and cannot be continued",
                                csv_path_));
    }
    std::vector<std::string> names;
    for (const auto name : SplitCsvLine(scan.header)) names.emplace_back(name);
    std::vector<std::string> expected;
    for (const auto& c : channels_) expected.push_back(c.name);
    if (names != expected) {
      throw IoError(fmt::format("{}:1: header '{}' does not match the channels of {} ('{}')",
                                csv_path_, scan.header, sidecar_path,
                                fmt::join(expected, ",")));
    }
    // A crash mid-write leaves a partial last line: cut it, and append after the last row.
    size_ = scan.last_end + 1;
    truncated_bytes_ = static_cast<long>(scan.size - size_);
    if (truncated_bytes_ > 0 && ::ftruncate(fd_, static_cast<off_t>(size_)) != 0) {
      throw IoError(fmt::format("{}: cannot cut the partial last line ({} bytes): {}",
                                csv_path_, truncated_bytes_, OsError()));
    }
    rows_ = scan.newlines - 1;
    if (rows_ > 0) {
      std::string line(static_cast<std::size_t>(scan.last_end - scan.prev_end - 1), '\0');
      if (::pread(fd_, line.data(), line.size(), static_cast<off_t>(scan.prev_end + 1)) !=
          static_cast<ssize_t>(line.size())) {
        throw IoError(fmt::format("{}: cannot read the last row: {}", csv_path_, OsError()));
      }
      const auto fields = SplitCsvLine(line);
      for (const auto field : fields) {
        const auto value = ParseCsvNumber(field);
        if (!value || fields.size() != channels_.size()) {
          throw IoError(fmt::format("{}:{}: the last row is not {} numbers: '{}'", csv_path_,
                                    scan.newlines, channels_.size(), line));
        }
        last_row_.push_back(*value);
      }
    }
  } catch (...) {
    ::close(fd_);
    fd_ = -1;
    throw;
  }
  previous_status_ = sidecar_.value("status", "");
  written_rows_ = rows_;
  if (policy_ == SyncPolicy::kBuffered) pending_.reserve(kJournalBlockBytes + 64 * 1024);
  last_write_ = last_sync_ = Now();
  published_ = true;
  status_is_running_ = false;
  ReserveNextSidecar();
}

}  // namespace hybridtest::io
