// See run_inputs.h.
#include "hybridtest/io/run_inputs.h"

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "hybridtest/common/error.h"
#include "hybridtest/io/digest.h"

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

// The content of one input file: the config's is the text the spec was compiled from.
InputText ReadInput(const RunInput& input, const RunSpec& spec) {
  InputText out{input, "", ""};
  if (input.role == "token") return out;  // a secret: never read, hashed or copied here
  if (input.role == "config") {
    out.text = spec.source.config_text;
  } else {
    std::error_code ec;
    if (!fs::is_regular_file(input.path, ec)) {
      throw IoError(fmt::format("{} ({} file): missing or not a regular file", input.path,
                                input.role));
    }
    // Read whole with stdio (GCC 12 warns -Wnull-dereference inside istreambuf_iterator).
    std::FILE* file = std::fopen(input.path.c_str(), "rb");
    if (file == nullptr) {
      throw IoError(fmt::format("{} ({} file): cannot be read: {}", input.path, input.role,
                                std::strerror(errno)));
    }
    char buffer[1 << 16];
    for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, file)) > 0;) {
      out.text.append(buffer, n);
    }
    const bool failed = std::ferror(file) != 0;
    std::fclose(file);
    if (failed) {
      throw IoError(fmt::format("{} ({} file): cannot be read to its end", input.path,
                                input.role));
    }
  }
  out.sha256 = Sha256Hex(out.text);
  return out;
}

}  // namespace

std::vector<InputText> ReadInputTexts(const RunSpec& spec) {
  std::vector<InputText> out;
  for (const RunInput& input : spec.source.files) out.push_back(ReadInput(input, spec));
  return out;
}

nlohmann::json RecordRunInputs(const std::vector<InputText>& inputs, const std::string& csv_path) {
  nlohmann::json record = nlohmann::json::array();
  for (const InputText& input : inputs) {
    nlohmann::json entry = {{"role", input.file.role},
                            {"path", RelativeToRun(input.file.path, csv_path)}};
    if (input.file.role != "token") entry["sha256"] = input.sha256;
    record.push_back(entry);
  }
  return record;
}

nlohmann::json InputTexts(const std::vector<InputText>& inputs) {
  nlohmann::json out = nlohmann::json::array();
  for (const InputText& input : inputs) {
    if (input.file.role == "token") continue;  // a secret: never copied
    // "fmu" (an FMU substructure's file, fmi/fmu_config.h): a zip archive, so its digest and
    // not its bytes (which are no UTF-8 text).
    if (input.file.role == "fmu") {
      out.push_back({{"role", input.file.role}, {"path", input.file.path},
                     {"sha256", input.sha256}, {"binary", true}});
      continue;
    }
    out.push_back({{"role", input.file.role}, {"path", input.file.path},
                   {"sha256", input.sha256}, {"text", input.text}});
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

void CheckRunInputs(const nlohmann::json& recorded, const RunSpec& spec,
                    const std::string& csv_path, std::string_view rule, std::string_view fix) {
  const std::vector<RunInput>& now = spec.source.files;
  std::vector<std::string> problems;
  if (!recorded.is_array() || recorded.size() != now.size()) {
    std::string names;
    for (const RunInput& input : now) {
      names += fmt::format("{}{} ({})", names.empty() ? "" : ", ", input.path, input.role);
    }
    problems.push_back(fmt::format("the run read {} files, its config now reads {}: {}",
                                   recorded.is_array() ? recorded.size() : 0, now.size(), names));
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
        digest = ReadInput(now[i], spec).sha256;
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
      "{}: {} (found from the run's directory, not the current one), and these differ:{}\n{}",
      csv_path, rule, list, fix));
}

}  // namespace hybridtest::io
