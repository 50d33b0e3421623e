#pragma once
// Journal: the crash-safe record of a run. Every committed step is appended as it happens to a
// CSV file whose first line holds the channel names; a JSON sidecar beside it holds the
// metadata (see docs/results-format.md). The CSV is the record of truth: a crash, a SIGKILL or
// a safety stop must lose no committed row, and no later run may destroy it (decision 0008:
// a new journal is staged until its first row; rows are written whole).
//
//   results/run.csv         t,q1,...,u1,...,r1,...[,r1_command,r1_position,r1_force,r1_lab_time]
//   results/run.meta.json   channels (unit, description), config copy, model parameters,
//                           software version, start time; statistics and status once finished
#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace hybridtest::io {

// One column of the journal. Units are SI ("m", "m/s", "rad", "rad/s", "N", "s").
struct Channel {
  std::string name;         // CSV header name, e.g. "q1"
  std::string unit;         // e.g. "m"
  std::string description;  // e.g. "tip deflection of blade 1"
};

// What the sidecar says about the run, besides the channels.
struct JournalMetadata {
  std::string command;      // the hybridtest subcommand that produced the run: "simulate", "run"
  std::string config_path;  // path of the config file as given
  std::string config_text;  // verbatim copy of the config file
  nlohmann::json model;     // {"name", "parameters": [{"name","value","unit","description"}],
                            //  "coordinates": [{"name","unit","description"}], "speeds": [...],
                            //  "slots": [{"name","coordinate","description"}]}
  nlohmann::json substructures = nlohmann::json::array();
                            // [{"slot":"r1","kind":"physical"|"numerical","description",
                            //   "channels": {"command","position","force","lab_time"}}]
  nlohmann::json extra = nlohmann::json::object();  // anything else worth keeping
};

// When rows reach the kernel (a killed process loses nothing) and the disk (a power cut loses
// nothing).
enum class SyncPolicy {
  kEveryRow,  // write + fsync after every row: a physical substructure is in the loop
              // (decision 0008: a committed row is on disk before the next trial moves steel)
  kBatched,   // write every row, fsync every `batch_rows` rows and at the end
  kBuffered,  // numerical runs: rows are collected in memory and written in blocks of
              // kJournalBlockBytes, and at least every kJournalWriteInterval; fsync at most
              // every kJournalSyncInterval of wall time, and at Flush(true)/Finish. A killed
              // process loses at most the rows of the last interval unless Flush() was called
              // (the runner calls it before it saves a run state); `batch_rows` is unused.
};

// kBuffered: the bounds on rows held in memory and on rows not yet on the disk.
inline constexpr std::size_t kJournalBlockBytes = 64 * 1024;  // [B]
inline constexpr double kJournalWriteInterval = 0.2;          // [s] of wall time
inline constexpr double kJournalSyncInterval = 1.0;           // [s] of wall time

// The tag of the constructor that reopens an existing journal (resume).
struct ReopenForAppend {};
inline constexpr ReopenForAppend kReopenForAppend{};

// Lifecycle of a new journal (docs/results-format.md, "Never destroyed"):
//   constructed  header and sidecar go to staged files "<csv>.partial" and
//                "<sidecar>.partial"; nothing exists yet at csv_path or its sidecar, and an
//                older run there is untouched;
//   first Append the row is written to the staged CSV, which is synced and then published:
//                the old sidecar (if any) is removed, the staged CSV renamed to csv_path, the
//                staged sidecar to the sidecar path (a crash in between leaves a CSV without
//                sidecar, never a CSV with another run's sidecar);
//   Finish       records statistics and status in the sidecar. A journal finished (or
//                destroyed) before its first Append removes its staged files: a run that
//                never committed a row leaves nothing behind.
// Every row is written whole or not at all: a failed or short write (full disk, file-size
// limit) is cut back to the last complete row before the IoError is thrown.
class Journal {
 public:
  // Stages a new journal (see above). Throws IoError naming the path if the directory is
  // missing or the staged files cannot be written.
  Journal(std::string csv_path, std::vector<Channel> channels, JournalMetadata metadata,
          SyncPolicy policy, int batch_rows = 1000);
  // Reopens the published journal at csv_path to append to it: reads its sidecar (channels,
  // metadata, status) and its CSV, checks that the header matches the sidecar's channels,
  // cuts a partial last line (a crash mid-write) and appends after the last complete row.
  // The sidecar's status is set back to "running" at the first new row. Throws IoError naming
  // file (and line) if either file is missing, unreadable or inconsistent.
  Journal(ReopenForAppend, std::string csv_path, SyncPolicy policy, int batch_rows = 1000);
  ~Journal();  // syncs; never throws (see Finish for what an unfinished journal records)
  Journal(const Journal&) = delete;
  Journal& operator=(const Journal&) = delete;

  // Appends one committed step; row.size() must equal the number of channels. Values are
  // written as the shortest text that reads back to the same double (csv.h). The first
  // Append of a new journal publishes it (written and synced at once, whatever the policy).
  // Throws IoError on a write failure, after cutting the file back to its last whole row.
  // durable = false: the row reaches the kernel (a killed process loses nothing) but is not
  // synced on its own even with kEveryRow; the next durable row's fsync covers it (a scheme's
  // intermediate rows between two specimen samples).
  void Append(std::span<const double> row, bool durable = true);

  // Writes the rows held in memory (kBuffered) to the kernel; with sync = true also fsyncs.
  // Afterwards a killed process loses no row appended so far. Cheap when nothing is pending.
  // Throws IoError as Append does (the rows not written are then lost and rows() says so).
  void Flush(bool sync = false);

  // Syncs the CSV and rewrites the sidecar (atomically) with the run's statistics and its
  // final status ("completed", or "stopped: <reason>"). The sidecar is written even if the
  // CSV cannot be synced; either failure then throws IoError. On a journal that was never
  // published it removes the staged files and writes nothing.
  void Finish(const nlohmann::json& statistics, const std::string& status);

  // Sets one top-level entry of the sidecar and rewrites it atomically at once (e.g. the
  // record of a resume). Throws IoError. Not allowed on an unpublished journal.
  void SetSidecarEntry(const std::string& key, nlohmann::json value);

  const std::string& csv_path() const { return csv_path_; }
  const std::vector<Channel>& channels() const { return channels_; }
  long rows() const { return rows_; }  // rows appended (0 = header only), kBuffered: some may
                                       // still be in memory until Flush()
  bool published() const { return published_; }
  const nlohmann::json& sidecar() const { return sidecar_; }
  // The values of the last row appended, or of a reopened journal's last complete row (empty
  // if it has none; the run state records them); on a reopened journal, the sidecar's status
  // found on reopening and the bytes of a partial last line cut off.
  const std::vector<double>& last_row() const { return last_row_; }
  const std::string& previous_status() const { return previous_status_; }
  long truncated_bytes() const { return truncated_bytes_; }

 private:
  void WriteRow(const std::string& line);   // whole or not at all, at size_
  void Publish();
  void Discard() noexcept;                  // removes the staged files
  void WriteSidecar(bool reserve_next);
  void ReserveNextSidecar();                // blocks for the next sidecar rewrite (full disk)
  void SyncCsv(long row);                   // throws IoError
  void WritePending();                      // writes pending_ whole, or cuts back and throws
  static double Now();                      // monotonic wall time [s]

  std::string csv_path_;
  std::vector<Channel> channels_;
  nlohmann::json sidecar_;
  SyncPolicy policy_;
  int batch_rows_;
  int fd_ = -1;
  std::int64_t size_ = 0;  // bytes of the CSV's complete lines [B]
  long rows_ = 0;
  long written_rows_ = 0;  // rows handed to the kernel (kBuffered: rows_ − rows in pending_)
  std::string pending_;    // kBuffered: whole rows not yet written
  double last_write_ = 0.0;  // Now() at the last write of pending_ [s]
  double last_sync_ = 0.0;   // Now() at the last fsync [s]
  bool unsynced_ = false;    // rows written since the last fsync
  bool published_ = false;
  bool finished_ = false;
  bool status_is_running_ = true;  // false on a reopened journal until its first new row
  std::string line_;  // reused row buffer: no allocation per Append once warmed up
  std::vector<double> last_row_;
  std::string previous_status_;
  long truncated_bytes_ = 0;
};

// The staged name of a file of a new run before it is published: "<path>.partial".
std::string StagedPath(const std::string& path);

// results/run.csv -> results/run.stages.csv: the per-stage record of a run with a physical
// slot (written by the runner with its own sidecar).
std::string StagesPath(const std::string& csv_path);

// Reads the sidecar of the run at csv_path. Throws IoError naming the sidecar if it is
// missing or not valid JSON.
nlohmann::json ReadSidecar(const std::string& csv_path);

// results/run.csv -> results/run.meta.json (any extension is replaced; none is appended to).
std::string SidecarPath(const std::string& csv_path);

}  // namespace hybridtest::io
