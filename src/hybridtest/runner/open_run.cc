// See open_run.h.
#include "hybridtest/runner/open_run.h"

#include <fmt/core.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <system_error>

#include "hybridtest/common/error.h"
#include "hybridtest/common/version.h"
#include "hybridtest/io/journal.h"
#include "hybridtest/io/output_budget.h"
#include "hybridtest/io/run_inputs.h"
#include "hybridtest/io/run_outputs.h"
#include "hybridtest/runner/run_record.h"

namespace hybridtest::runner {

// The one maker of a locked OpenedRun.
struct OpenedRunAccess {
  static OpenedRun Opened(io::RunLock lock, std::string journal) {
    return OpenedRun(std::move(lock), std::move(journal));
  }
};

namespace {

namespace fs = std::filesystem;

bool HasPhysical(const io::RunSpec& spec) {
  return std::any_of(spec.substructures.begin(), spec.substructures.end(),
                     [](const auto& s) { return s.is_physical(); });
}

// What a resumed run has written already (its journal and stage record). Unit: [bytes].
std::uintmax_t WrittenBytes(const std::string& csv) {
  std::uintmax_t bytes = 0;
  for (const std::string& file : {csv, io::StagesPath(csv)}) {
    std::error_code ec;
    const std::uintmax_t size = fs::file_size(file, ec);
    if (!ec) bytes += size;
  }
  return bytes;
}

std::string HostName() {
  char host[256] = {};
  if (::gethostname(host, sizeof host - 1) != 0) host[0] = '\0';
  return host;
}

// Where a run's record comes from (io::SourceSpec::provenance).
nlohmann::json Provenance(const std::string& csv, const std::vector<io::InputText>& inputs,
                          const OpenRunOptions& options) {
  std::error_code ec;
  const fs::path output = fs::absolute(csv, ec);
  nlohmann::json provenance = {
      {"software", {{"name", "hybridtest"}, {"version", kVersion}, {"git", kGitDescribe},
                    {"build_type", kBuildType}}},
      {"host", HostName()},
      {"command_line", options.command_line},
      {"working_directory", fs::current_path(ec).string()},
      {"output", ec ? csv : output.lexically_normal().string()},
      {"inputs", io::InputTexts(inputs)}};
  if (options.provenance.is_object() && !options.provenance.empty()) {
    provenance.merge_patch(options.provenance);
  }
  return provenance;
}

// Steps 1–5 (open_run.h). `lock`: held by a resume since before it read the run; `resume`:
// the run's files are continued and its record checked, not written.
OpenedRun Open(io::RunSpec& spec, const OpenRunOptions& options, bool resume,
               std::optional<io::RunLock> lock) {
  if (!spec.output.files) return {};
  const std::string csv = spec.output.csv_path;
  if (csv.empty()) {
    throw ConfigError("run spec: output.files is set but output.csv_path is empty: give the "
                      "journal's path, or set output.files = false for a run in memory");
  }
  // 1. One master per run: the lock comes before any file of the run is looked at.
  if (!lock) {
    const fs::path parent = fs::path(csv).parent_path();
    if (!parent.empty()) fs::create_directories(parent);
    lock.emplace(io::RunLock::Acquire(csv, spec.output.command));
  }
  // 2. Results are never destroyed: an input is never an output, only regular files are
  //    written, an earlier run is replaced only when asked (a resume continues its own).
  io::CheckRunOutputs(csv, io::RunInputFiles(spec.source.files), options.overwrite || resume);
  // 3. The journal and stage record must fit on the disk (a resume: what is still to come).
  std::uintmax_t bytes = EstimateRunOutputBytes(spec);
  if (resume) bytes -= std::min(bytes, WrittenBytes(csv));
  io::CheckOutputFits(csv, bytes);
  // 4. The files the compile read: recorded, or (resume) checked against the record.
  if (resume) {
    io::CheckRunInputs(spec.source.inputs, spec, csv);
    // The record and provenance stay the run's own.
    return OpenedRunAccess::Opened(std::move(*lock), csv);
  }
  const std::vector<io::InputText> inputs = io::ReadInputTexts(spec);
  spec.source.inputs = io::RecordRunInputs(inputs, csv);
  // 5. Where the record comes from.
  spec.source.provenance = Provenance(csv, inputs, options);
  if (!spec.source.bench_address.empty()) spec.source.provenance["bench"] = spec.source.bench_address;
  return OpenedRunAccess::Opened(std::move(*lock), csv);
}

}  // namespace

std::uintmax_t EstimateRunOutputBytes(const io::RunSpec& spec) {
  const bool stages = HasPhysical(spec) && spec.output.record_stages;
  return io::EstimateOutputBytes(
      MaxJournalRows(spec), static_cast<int>(JournalChannels(spec).size()),
      spec.scheme.config.kind == schemes::SchemeKind::kRungeKutta ? spec.scheme.tableau.stages()
                                                                  : 1,
      stages ? static_cast<int>(StageChannels(spec).size()) : 0);
}

OpenedRun OpenRun(io::RunSpec& spec, OpenRunOptions options) {
  return Open(spec, options, /*resume=*/false, std::nullopt);
}

OpenedResume OpenResume(const OpenResumeOptions& options) {
  const ResumeRequest& request = options.request;
  if (!fs::is_regular_file(request.csv)) {
    throw ConfigError(fmt::format("{}: no such journal: give the CSV of the run to resume",
                                  request.csv));
  }
  // 1. One master per run: nothing of the run is read before the lock is held.
  io::RunLock lock = io::RunLock::Acquire(request.csv, "resume");
  ResumePlan plan = PlanResume(request);
  if (options.planned) options.planned(plan);
  ResumeSetup setup = PrepareResume(plan, request, options.set, options.command_line,
                                    options.bench_address, options.edit);
  // 2–4, with the lock held since before the run was read.
  OpenedRun opened = Open(setup.spec, {.command_line = options.command_line}, /*resume=*/true,
                          std::move(lock));
  return {std::move(plan), std::move(setup), std::move(opened)};
}

}  // namespace hybridtest::runner
