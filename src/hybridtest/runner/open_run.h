#pragma once
// The front door: one call opens a run for writing, the same for the command line's `run`,
// `simulate` and `resume`, Python's run/simulate/resume, a campaign's cases and
// `plan --keep` (docs/decisions/, "one front door"). OpenRun opens a new run from its compiled
// RunSpec; OpenResume opens a stopped one from its journal (it reads and compiles the run
// itself, so that no caller holds a lock or reads a run's state on its own). Before any
// substructure is built, activated or moved, in this order:
//
//   1. the lock: one master per run (io/run_lock.h), taken before any file of the run is
//      looked at (a resume: before its state is read or its config compiled);
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
// open, and OpenRun only returns an empty handle. The OpenedRun (opened_run.h) is what a
// file-backed Session is made from: Session(spec, std::move(opened)).
#include <nlohmann/json.hpp>

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "hybridtest/io/run_lock.h"
#include "hybridtest/io/run_spec.h"
#include "hybridtest/runner/opened_run.h"
#include "hybridtest/runner/resume_plan.h"

namespace hybridtest::runner {

struct OpenRunOptions {
  bool overwrite = false;     // --overwrite: replace an earlier, completed run's files
  std::string command_line{};  // how the run was started, for the provenance
  // Merged into the provenance (RFC 7386 merge patch), e.g. a campaign's MPI library version
  // under "software".
  nlohmann::json provenance = nlohmann::json::object();
};

// Opens spec's run for writing (steps 1–5 above) and fills spec.source.inputs and
// spec.source.provenance. The journal's folder is created if missing. Throws ConfigError for a
// refusal (another process holds the run, an output onto an input or onto an earlier run, a
// disk too small, a resumed run's files changed) and IoError for a file that cannot be read.
[[nodiscard]] OpenedRun OpenRun(io::RunSpec& spec, OpenRunOptions options = {});

// What a resume of a stopped run asks for (`hybridtest resume`, Python's resume()).
struct OpenResumeOptions {
  ResumeRequest request;            // the journal and the operator's tolerances
  std::vector<std::string> set{};   // KEY=VALUE changes (resume_changes.h)
  std::string command_line{};       // how the resume was started, for its record
  std::optional<std::string> bench_address{};  // --bench; unset: the one the run recorded
  // Changes the compiled spec before the changes apply (a caller's own transfer systems).
  std::function<void(io::RunSpec&)> edit{};
  // Told the plan once the run is read, before its config is compiled (the operator's notes).
  std::function<void(const ResumePlan&)> planned{};
};

// A stopped run opened again: what it continues from, what it runs, and its lock.
struct OpenedResume {
  ResumePlan plan;
  ResumeSetup setup;
  OpenedRun opened;
};

// Opens the run of options.request.csv for a resume: the lock (step 1) before anything of the
// run is read, then the run read and checked (PlanResume), its config compiled (PrepareResume),
// then steps 2–4 for a continued run: its files are neither refused as an earlier run's nor
// replaced, the disk must hold what is still to come, and the files the compile read must be
// the ones its record names; its record and provenance stay its own. Throws ConfigError (no
// such journal, a run another process holds, every refusal of PlanResume and PrepareResume, an
// input changed) and IoError.
[[nodiscard]] OpenedResume OpenResume(const OpenResumeOptions& options);

// The bytes the run's journal and stage record may need, at most (io::EstimateOutputBytes
// over MaxJournalRows and the channels). Unit: [bytes].
std::uintmax_t EstimateRunOutputBytes(const io::RunSpec& spec);

}  // namespace hybridtest::runner
