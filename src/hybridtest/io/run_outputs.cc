// See run_outputs.h.
#include "hybridtest/io/run_outputs.h"

#include <fmt/format.h>

#include <filesystem>
#include <system_error>

#include "hybridtest/common/error.h"
#include "hybridtest/io/journal.h"

namespace hybridtest::io {

namespace fs = std::filesystem;

std::vector<std::string> RunOutputFiles(const std::string& csv_path) {
  const std::string stages = StagesPath(csv_path);
  return {csv_path, SidecarPath(csv_path), stages, SidecarPath(stages)};
}

std::vector<std::string> RunInputFiles(const SimulationConfig& cfg) {
  std::vector<std::string> inputs{cfg.input.path()};
  const YAML::Node subs = cfg.input.root()["substructures"];
  if (!subs || !subs.IsMap()) return inputs;
  // The same rule as MakeSubstructures: a bench file is relative to the config's directory.
  for (const auto& slot : subs) {
    if (!slot.second.IsMap()) continue;
    const YAML::Node transfer = slot.second["transfer"];
    if (!transfer || !transfer.IsMap() || !transfer["config"] || !transfer["config"].IsScalar()) {
      continue;
    }
    fs::path file = transfer["config"].as<std::string>();
    if (file.is_relative()) file = fs::path(cfg.input.path()).parent_path() / file;
    inputs.push_back(file.string());
  }
  return inputs;
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
  for (const std::string& out : RunOutputFiles(csv_path)) {
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
  if (overwrite) return;
  for (const std::string& out : RunOutputFiles(csv_path)) {
    std::error_code ec;
    if (fs::exists(fs::symlink_status(out, ec)) && !ec) {
      throw ConfigError(fmt::format(
          "{}: exists already (an earlier run); pass --overwrite to replace that run, or "
          "choose another --out",
          out));
    }
  }
}

}  // namespace hybridtest::io
