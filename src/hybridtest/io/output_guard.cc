// See output_guard.h.
#include "hybridtest/io/output_guard.h"

#include <fmt/format.h>
#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <system_error>

#include "hybridtest/common/error.h"
#include "hybridtest/io/journal.h"
#include "hybridtest/io/run_lock.h"
#include "hybridtest/io/run_outputs.h"

namespace hybridtest::io {

namespace fs = std::filesystem;

namespace {

// The recorded inputs [{role, path}] of a sidecar's extra.inputs or a run state's inputs, paths
// relative to the journal's directory.
void AddRecordedInputs(const nlohmann::json& inputs, const fs::path& dir, const std::string& run,
                       std::vector<ProtectedFile>& out) {
  if (!inputs.is_array()) return;
  for (const auto& entry : inputs) {
    if (!entry.is_object() || !entry.contains("path") || !entry["path"].is_string()) continue;
    fs::path path = entry["path"].get<std::string>();
    if (path.is_relative()) path = dir / path;
    const std::string role = entry.value("role", std::string("input"));
    out.push_back({path.string(), fmt::format("the {} file of {}", role, run)});
  }
}

// A file type for a message.
const char* KindOf(mode_t mode) {
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode) || S_ISBLK(mode)) return "a device";
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

}  // namespace

std::vector<ProtectedFile> RunProtectedFiles(const std::string& csv_path,
                                             const std::string& label) {
  const std::string run = label.empty() ? csv_path : label;
  const std::string stages = StagesPath(csv_path);
  std::vector<ProtectedFile> files = {
      {csv_path, fmt::format("the journal of {}", run)},
      {SidecarPath(csv_path), fmt::format("the sidecar of {}", run)},
      {stages, fmt::format("the stage record of {}", run)},
      {SidecarPath(stages), fmt::format("the stage record's sidecar of {}", run)},
      {RunStatePath(csv_path), fmt::format("the run state of {}", run)},
      {RunLockPath(csv_path), fmt::format("the lock of {}", run)},
      {StagedPath(csv_path), fmt::format("the staged journal of {}", run)},
      {StagedPath(SidecarPath(csv_path)), fmt::format("the staged sidecar of {}", run)},
  };
  const fs::path dir = fs::path(csv_path).parent_path();
  // What the run read, as recorded by the run itself.
  try {
    const nlohmann::json sidecar = ReadSidecar(csv_path);
    if (sidecar.is_object()) {
      if (sidecar.contains("extra") && sidecar["extra"].is_object() &&
          sidecar["extra"].contains("inputs")) {
        AddRecordedInputs(sidecar["extra"]["inputs"], dir, run, files);
      }
      if (sidecar.contains("config_path") && sidecar["config_path"].is_string() &&
          !sidecar["config_path"].get<std::string>().empty()) {
        // As given on the command line (relative to where the run was started): a best guess.
        files.push_back({sidecar["config_path"].get<std::string>(),
                         fmt::format("the config file of {}", run)});
      }
    }
  } catch (const std::exception&) {
    // No sidecar (or a damaged one): its run's own files are still protected above.
  }
  return files;
}

void CheckOutputFile(const std::string& out, const std::vector<ProtectedFile>& inputs,
                     const std::string& option) {
  // The type first, without opening anything (a FIFO would block an open for writing).
  struct stat st {};
  if (::stat(out.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
    throw ConfigError(fmt::format(
        "{} {}: is {}; hybridtest writes its outputs to regular files only: choose a file "
        "name, e.g. {} results/report.html", option, out, KindOf(st.st_mode), option));
  }
  for (const ProtectedFile& in : inputs) {
    if (in.path.empty() || !SameFile(out, in.path)) continue;
    throw ConfigError(fmt::format(
        "{} {}: is {} ({}), which this command reads or which belongs to a run; writing there "
        "would destroy it. Nothing was written: choose another {} path",
        option, out, in.role, in.path, option));
  }
}

void CheckOutputDirectory(const std::string& dir, const std::vector<ProtectedFile>& inputs,
                          const std::string& option,
                          const std::vector<std::string>& written_names,
                          const std::vector<std::string>& written_extensions) {
  struct stat st {};
  if (::stat(dir.c_str(), &st) == 0 && !S_ISDIR(st.st_mode)) {
    const bool is_input = std::any_of(inputs.begin(), inputs.end(), [&](const ProtectedFile& f) {
      return !f.path.empty() && SameFile(dir, f.path);
    });
    throw ConfigError(fmt::format(
        "{} {}: is {}{}, not a directory; {} names the directory the figures go into: choose "
        "a directory (it is created if missing)",
        option, dir, S_ISREG(st.st_mode) ? "a file" : KindOf(st.st_mode),
        is_input ? " this command reads" : "", option));
  }
  for (const ProtectedFile& in : inputs) {
    if (in.path.empty()) continue;
    const fs::path file(in.path);
    std::error_code ec;
    const fs::path parent = file.parent_path().empty() ? fs::path(".") : file.parent_path();
    if (!fs::exists(dir, ec) || !fs::exists(file, ec) || !SameFile(parent.string(), dir)) {
      continue;
    }
    const std::string name = file.filename().string();
    const std::string ext = file.extension().string();
    const bool clash =
        std::find(written_names.begin(), written_names.end(), name) != written_names.end() ||
        std::find(written_extensions.begin(), written_extensions.end(), ext) !=
            written_extensions.end();
    if (!clash) continue;
    throw ConfigError(fmt::format(
        "{} {}: holds {} ({}), a file this command would write over; nothing was written: "
        "choose another {} directory",
        option, dir, in.role, in.path, option));
  }
}

}  // namespace hybridtest::io
