// See open_run.h.
#include "hybridtest/runner/open_run.h"

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <system_error>

#include "hybridtest/common/version.h"
#include "hybridtest/io/journal.h"
#include "hybridtest/io/output_budget.h"
#include "hybridtest/io/run_inputs.h"
#include "hybridtest/io/run_outputs.h"
#include "hybridtest/runner/run_record.h"

namespace hybridtest::runner {
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
  if (!spec.output.files) return {};
  const std::string csv = spec.output.csv_path;
  if (csv.empty()) {
    throw ConfigError("run spec: output.files is set but output.csv_path is empty: give the "
                      "journal's path, or set output.files = false for a run in memory");
  }
  // 1. One master per run: the lock comes before any file of the run is looked at.
  std::optional<io::RunLock> lock = std::move(options.lock);
  if (!lock) {
    const fs::path parent = fs::path(csv).parent_path();
    if (!parent.empty()) fs::create_directories(parent);
    lock.emplace(io::RunLock::Acquire(csv, spec.output.command));
  }
  // 2. Results are never destroyed: an input is never an output, only regular files are
  //    written, an earlier run is replaced only when asked (a resume continues its own).
  io::CheckRunOutputs(csv, io::RunInputFiles(spec.source.files),
                      options.overwrite || options.resume);
  // 3. The journal and stage record must fit on the disk (a resume: what is still to come).
  std::uintmax_t bytes = EstimateRunOutputBytes(spec);
  if (options.resume) bytes -= std::min(bytes, WrittenBytes(csv));
  io::CheckOutputFits(csv, bytes);
  // 4. The files the compile read: recorded, or (resume) checked against the record.
  if (options.resume) {
    io::CheckRunInputs(spec.source.inputs, spec, csv);
    return OpenedRun(std::move(*lock));  // the record and provenance stay the run's own
  }
  const std::vector<io::InputText> inputs = io::ReadInputTexts(spec);
  spec.source.inputs = io::RecordRunInputs(inputs, csv);
  // 5. Where the record comes from.
  spec.source.provenance = Provenance(csv, inputs, options);
  if (!spec.source.bench_address.empty()) spec.source.provenance["bench"] = spec.source.bench_address;
  return OpenedRun(std::move(*lock));
}

}  // namespace hybridtest::runner
