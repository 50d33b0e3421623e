#pragma once
// The front door: one call opens a run for writing, the same for the command line's `run`,
// `simulate` and `resume`, Python's run/simulate/resume, a campaign's cases and
// `plan --keep` (docs/decisions/, "one front door"). Given a compiled RunSpec, before any
// substructure is built, activated or moved, in this order:
//
//   1. the lock: one master per run (io/run_lock.h), taken before any file of the run is
//      looked at. A resume takes it itself before it reads the run's state, and hands it in;
//   2. the output guards (io/run_outputs.h, CheckRunOutputs): no output is a file the run read
//      (spec.source.files: what the compile opened), nor anything but a regular file; an
//      earlier run's files are replaced only with `overwrite`;
//   3. the disk budget (io/output_budget.h): the journal and stage record must fit;
//   4. the input record (io/run_inputs.h) from the files the compile read — config, model
//      file, its `csv:` tables, bench files, token files by path only — into
//      spec.source.inputs; a resume instead checks them against the record it continues;
//   5. the provenance: software, host, command line, working directory, output, and every
//      input but a token verbatim, into spec.source.provenance (a resume keeps the one its
//      sidecar holds).
//
// Every refusal is a ConfigError (exit 2 on the command line) with the same message from every
// entry point. A run in memory (spec.output.files == false) writes nothing: there is nothing to
// open, and OpenRun only returns an empty handle.
#include <nlohmann/json.hpp>

#include <optional>
#include <string>

#include "hybridtest/io/run_lock.h"
#include "hybridtest/io/run_spec.h"

namespace hybridtest::runner {

struct OpenRunOptions {
  bool overwrite = false;     // --overwrite: replace an earlier, completed run's files
  std::string command_line{};  // how the run was started, for the provenance
  // Merged into the provenance (RFC 7386 merge patch), e.g. a campaign's MPI library version
  // under "software".
  nlohmann::json provenance = nlohmann::json::object();
  // A resume: the run's files are continued (neither refused as an earlier run's nor
  // replaced), the files the compile read must be the ones its record names
  // (spec.source.inputs, from its run state), and its provenance is the recorded one.
  bool resume = false;
  // The lock, if the caller holds it already (a resume, which locks before reading the run).
  std::optional<io::RunLock> lock{};
};

// What an open run holds until it ends: its lock (none for a run in memory). Released, and
// the lock file removed, when destroyed.
class OpenedRun {
 public:
  OpenedRun() = default;
  explicit OpenedRun(io::RunLock lock) { lock_.emplace(std::move(lock)); }
  bool locked() const { return lock_.has_value(); }

 private:
  std::optional<io::RunLock> lock_;
};

// Opens spec's run for writing (steps 1–5 above) and fills spec.source.inputs and
// spec.source.provenance. The journal's folder is created if missing. Throws ConfigError for a
// refusal (another process holds the run, an output onto an input or onto an earlier run, a
// disk too small, a resumed run's files changed) and IoError for a file that cannot be read.
[[nodiscard]] OpenedRun OpenRun(io::RunSpec& spec, OpenRunOptions options = {});

// The bytes the run's journal and stage record may need, at most (io::EstimateOutputBytes
// over MaxJournalRows and the channels). Unit: [bytes].
std::uintmax_t EstimateRunOutputBytes(const io::RunSpec& spec);

}  // namespace hybridtest::runner
