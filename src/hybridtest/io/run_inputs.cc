// See run_inputs.h.
#include "hybridtest/io/run_inputs.h"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "hybridtest/common/error.h"
#include "hybridtest/io/digest.h"
#include "hybridtest/io/run_outputs.h"

namespace hybridtest::io {
namespace {

namespace fs = std::filesystem;

fs::path RunDirectory(const std::string& csv_path) {
  return fs::absolute(fs::path(csv_path)).parent_path().lexically_normal();
}

// `path` relative to the run's directory.
std::string RelativeToRun(const std::string& path, const std::string& csv_path) {
  const fs::path absolute = fs::absolute(fs::path(path)).lexically_normal();
  const fs::path relative = absolute.lexically_relative(RunDirectory(csv_path));
  return relative.empty() ? absolute.string() : relative.string();
}

std::string DigestOf(const RunInput& input, const SimulationConfig& cfg) {
  if (input.role == "token") return "";
  if (input.role == "config") return Sha256Hex(cfg.input.text());
  return Sha256OfFile(input.path);
}

}  // namespace

nlohmann::json RecordRunInputs(const SimulationConfig& cfg, const std::string& csv_path) {
  nlohmann::json record = nlohmann::json::array();
  for (const RunInput& input : RunInputs(cfg)) {
    nlohmann::json entry = {{"role", input.role}, {"path", RelativeToRun(input.path, csv_path)}};
    if (input.role != "token") entry["sha256"] = DigestOf(input, cfg);
    record.push_back(entry);
  }
  return record;
}

nlohmann::json InputTexts(const SimulationConfig& cfg) {
  nlohmann::json out = nlohmann::json::array();
  for (const RunInput& input : RunInputs(cfg)) {
    if (input.role == "token") continue;  // a secret: never copied
    std::string text = cfg.input.text();
    if (input.role != "config") {
      std::ifstream file(input.path, std::ios::binary);
      text.assign(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
    }
    out.push_back({{"role", input.role}, {"path", input.path}, {"sha256", Sha256Hex(text)},
                   {"text", text}});
  }
  return out;
}

std::string RecordedConfigPath(const nlohmann::json& inputs, const std::string& csv_path) {
  for (const auto& entry : inputs) {
    if (entry.is_object() && entry.value("role", "") == "config" && entry["path"].is_string()) {
      const fs::path path = entry["path"].get<std::string>();
      return (path.is_absolute() ? path : RunDirectory(csv_path) / path).lexically_normal().string();
    }
  }
  throw ConfigError(fmt::format("{}: the run's record names no config among its inputs; it "
                                "cannot be resumed", csv_path));
}

void CheckRunInputs(const nlohmann::json& recorded, const SimulationConfig& cfg,
                    const std::string& csv_path) {
  const std::vector<RunInput> now = RunInputs(cfg);
  std::vector<std::string> problems;
  if (!recorded.is_array() || recorded.size() != now.size()) {
    problems.push_back(fmt::format("the run read {} files, its config now names {}",
                                   recorded.is_array() ? recorded.size() : 0, now.size()));
  } else {
    for (std::size_t i = 0; i < now.size(); ++i) {
      const auto& entry = recorded[i];
      const std::string role = entry.is_object() ? entry.value("role", "") : "";
      if (role != now[i].role) {
        problems.push_back(fmt::format("{}: recorded as a {} file, now a {} file", now[i].path,
                                       role, now[i].role));
        continue;
      }
      if (role == "token") continue;
      std::string digest;
      try {
        digest = DigestOf(now[i], cfg);
      } catch (const Error& e) {
        problems.push_back(fmt::format("{} ({} file): missing or unreadable: {}", now[i].path,
                                       role, e.what()));
        continue;
      }
      const std::string expected = entry.value("sha256", "");
      if (digest != expected) {
        problems.push_back(fmt::format("{} ({} file): changed since the run started (sha256 {} "
                                       "now, {} when the run read it)", now[i].path, role,
                                       digest, expected));
      }
    }
  }
  if (problems.empty()) return;
  std::string list;
  for (const auto& p : problems) list += "\n  " + p;
  throw ConfigError(fmt::format(
      "{}: resume continues a run only with the files it started with (found from the run's "
      "directory, not the current one), and these differ:{}\nRestore those files, or start a "
      "new run with hybridtest run --out NEW.csv", csv_path, list));
}

}  // namespace hybridtest::io
