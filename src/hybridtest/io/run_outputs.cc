// See run_outputs.h.
#include "hybridtest/io/run_outputs.h"

#include <fmt/format.h>

#include <filesystem>
#include <system_error>

#include "hybridtest/common/error.h"
#include "hybridtest/io/journal.h"
#include "hybridtest/io/run_lock.h"

namespace hybridtest::io {

namespace fs = std::filesystem;

std::string RunStatePath(const std::string& csv_path) {
  const fs::path p(csv_path);
  return (p.parent_path() / (p.stem().string() + ".state.json")).string();
}

std::vector<std::string> RunOutputFiles(const std::string& csv_path) {
  const std::string stages = StagesPath(csv_path);
  return {csv_path, SidecarPath(csv_path), stages, SidecarPath(stages)};
}

std::vector<std::string> RunInputFiles(const std::vector<RunInput>& files) {
  std::vector<std::string> paths;
  for (const RunInput& input : files) paths.push_back(input.path);
  return paths;
}

bool SameFile(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (fs::equivalent(a, b, ec) && !ec) return true;
  const fs::path ca = fs::weakly_canonical(fs::absolute(a), ec);
  if (ec) return false;
  const fs::path cb = fs::weakly_canonical(fs::absolute(b), ec);
  return !ec && ca == cb;
}

void CheckRunOutputs(const std::string& csv_path, const std::vector<std::string>& inputs,
                     bool overwrite) {
  std::vector<std::string> outputs = RunOutputFiles(csv_path);
  outputs.push_back(RunStatePath(csv_path));
  // The lock file is written and removed by the run too (run_lock.h): never an input.
  std::vector<std::string> written = outputs;
  written.push_back(RunLockPath(csv_path));
  for (const std::string& out : written) {
    for (const std::string& in : inputs) {
      if (!SameFile(out, in)) continue;
      const std::string what =
          out == csv_path ? fmt::format("the output is the same file as {}", in)
                          : fmt::format("its companion {} would be written over {}", out, in);
      throw ConfigError(fmt::format("{}: {}, a file it reads; choose another --out "
                                    "(--overwrite does not allow this)",
                                    csv_path, what));
    }
  }
  // Only regular files are ever replaced: a device node, a FIFO, a directory or a symlink at
  // an output's name is refused even with --overwrite (as root, replacing /dev/null would
  // break the machine; a symlink would write through to whatever it names).
  for (const std::string& out : outputs) {
    std::error_code ec;
    const fs::file_status st = fs::symlink_status(out, ec);
    if (ec || !fs::exists(st) || fs::is_regular_file(st)) continue;
    const char* kind = fs::is_symlink(st)     ? "a symbolic link"
                       : fs::is_directory(st) ? "a directory"
                       : fs::is_fifo(st)      ? "a FIFO"
                       : (fs::is_character_file(st) || fs::is_block_file(st)) ? "a device"
                                                                                : "not a regular file";
    throw ConfigError(fmt::format("{}: is {}; a run writes only regular files and never "
                                  "replaces anything else (--overwrite does not allow this): "
                                  "choose another --out", out, kind));
  }
  if (overwrite) return;
  // A run that did not complete is continued, never replaced by default: resume comes first.
  {
    std::error_code ec;
    if (fs::is_regular_file(csv_path, ec) && fs::is_regular_file(SidecarPath(csv_path), ec)) {
      std::string status = "completed";  // an unreadable sidecar is no run to continue
      try {
        status = ReadSidecar(csv_path).value("status", "");
      } catch (const std::exception&) {
      }
      if (status != "completed") {
        const bool killed = status == "running";
        throw ConfigError(fmt::format(
            "{}: holds a run that did not finish ({}). Continue it with:\n"
            "    hybridtest resume {}\n"
            "every committed step is kept. Or choose another --out; --overwrite would destroy "
            "its committed steps",
            csv_path,
            killed ? "status 'running' while no process holds it: it was killed"
                   : "status '" + status + "'",
            csv_path));
      }
    }
  }
  for (const std::string& out : outputs) {
    std::error_code ec;
    if (fs::exists(fs::symlink_status(out, ec)) && !ec) {
      throw ConfigError(fmt::format(
          "{}: exists already (an earlier, completed run); choose another --out, or pass "
          "--overwrite to replace that run",
          out));
    }
  }
}

}  // namespace hybridtest::io
