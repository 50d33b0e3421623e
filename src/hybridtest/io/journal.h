#pragma once
// Journal: the crash-safe record of a run. Every committed step is appended as it happens to a
// CSV file whose first line holds the channel names; a JSON sidecar beside it holds the
// metadata (see docs/results-format.md). The CSV is the record of truth: a crash, a SIGKILL or
// a safety stop must lose no committed row.
//
//   results/run.csv         t,q1,...,u1,...,r1,...[,r1_command,r1_position,r1_force,r1_lab_time]
//   results/run.meta.json   channels (unit, description), config copy, model parameters,
//                           software version, start time; statistics and status once finished
#include <nlohmann/json.hpp>

#include <cstdio>
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

// When rows reach the disk.
enum class SyncPolicy {
  kEveryRow,  // fflush + fsync after every row: a physical substructure is in the loop
  kBatched,   // fflush every row, fsync every `batch_rows` rows and at the end: numerical runs
};

class Journal {
 public:
  // Creates (truncates) csv_path, writes the names line and the sidecar. Throws IoError
  // naming the path if the directory is missing or the file cannot be written.
  Journal(std::string csv_path, std::vector<Channel> channels, JournalMetadata metadata,
          SyncPolicy policy, int batch_rows = 1000);
  ~Journal();  // flushes and syncs; never throws
  Journal(const Journal&) = delete;
  Journal& operator=(const Journal&) = delete;

  // Appends one committed step; row.size() must equal the number of channels. Values are
  // written with 17 significant digits. Throws IoError on a write failure.
  // durable = false: the row reaches the kernel (a killed process loses nothing) but is not
  // synced on its own even with kEveryRow; the next durable row's fsync covers it (a scheme's
  // intermediate rows between two specimen samples).
  void Append(std::span<const double> row, bool durable = true);

  // Syncs the CSV and rewrites the sidecar (atomically: write + rename) with the run's
  // statistics and its final status ("completed", or "stopped: <reason>").
  void Finish(const nlohmann::json& statistics, const std::string& status);

  const std::string& csv_path() const { return csv_path_; }
  const std::vector<Channel>& channels() const { return channels_; }
  long rows() const { return rows_; }

 private:
  std::string csv_path_;
  std::vector<Channel> channels_;
  nlohmann::json sidecar_;
  SyncPolicy policy_;
  int batch_rows_;
  std::FILE* file_ = nullptr;
  long rows_ = 0;
  bool finished_ = false;
  std::string line_;  // reused row buffer: no allocation per Append once warmed up
};

// results/run.csv -> results/run.meta.json (any extension is replaced; none is appended to).
std::string SidecarPath(const std::string& csv_path);

}  // namespace hybridtest::io
