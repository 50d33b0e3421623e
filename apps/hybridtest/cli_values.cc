// See cli_values.h.
#include "cli_values.h"

#include <fmt/core.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "hybridtest/common/error.h"
#include "hybridtest/common/input_file.h"

namespace hybridtest::app {

std::vector<double> ParseNumberList(const std::string& text, const std::string& option) {
  std::vector<double> values;
  std::stringstream ss(text);
  std::string item;
  int index = 0;
  while (std::getline(ss, item, ',')) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || end == item.c_str() || *end != '\0' || !std::isfinite(v)) {
      throw ConfigError(fmt::format("{}: entry {} is '{}': expected a finite number; give the "
                                    "values comma-separated without spaces, e.g. 0,0.01,0,0",
                                    option, index + 1, item));
    }
    values.push_back(v);
    ++index;
  }
  return values;
}

namespace {

// A validator: the value must be a finite number (whole text) with `ok(v)`.
CLI::Validator MakeNumberValidator(const char* name, const char* expected,
                                   bool (*ok)(double)) {
  return CLI::Validator(
      [expected, ok](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (text.empty() || end == text.c_str() || *end != '\0' || !std::isfinite(v) || !ok(v)) {
          return fmt::format("'{}': expected {}", text, expected);
        }
        return {};
      },
      expected, name);
}

}  // namespace

const CLI::Validator& FiniteNumber() {
  static const CLI::Validator v =
      MakeNumberValidator("FINITE", "a finite number", [](double) { return true; });
  return v;
}

const CLI::Validator& PositiveFiniteNumber() {
  static const CLI::Validator v = MakeNumberValidator(
      "POSITIVE", "a finite number greater than 0", [](double x) { return x > 0.0; });
  return v;
}

const CLI::Validator& NonNegativeFiniteNumber() {
  static const CLI::Validator v = MakeNumberValidator(
      "NONNEGATIVE", "a finite number of 0 or more", [](double x) { return x >= 0.0; });
  return v;
}

CLI::Validator FiniteRange(double min, double max) {
  return CLI::Validator(
      [min, max](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (text.empty() || end == text.c_str() || *end != '\0' || !std::isfinite(v) ||
            v < min || v > max) {
          return fmt::format("'{}': expected a finite number from {} to {}", text, min, max);
        }
        return {};
      },
      fmt::format("NUMBER in [{} - {}]", min, max), "FINITE_RANGE");
}

const CLI::Validator& RegularInputFile() {
  static const CLI::Validator v(
      [](std::string& path) -> std::string {
        const std::string problem = RegularFileProblem(path);
        if (problem.empty()) return {};
        if (problem == "no such file") {
          return fmt::format("'{}': no such file; check the path (relative paths start at the "
                             "current directory)", path);
        }
        return fmt::format("'{}': not a regular file ({}); give a file here", path, problem);
      },
      "FILE", "REGULAR_FILE");
  return v;
}

io::RunData LoadRunInput(const std::string& path, const std::string& what) {
  RequireRegularFile(path, what, "run journal (the .csv file written by 'hybridtest run')");
  try {
    return io::LoadRun(path);
  } catch (const IoError& e) {
    throw ConfigError(fmt::format("{} = '{}': not a readable run: {}", what, path, e.what()));
  }
}

void CheckJournalHeader(const std::string& path, const std::string& what) {
  RequireRegularFile(path, what, "run journal (the .csv file written by 'hybridtest run')");
  std::ifstream in(path, std::ios::binary);  // a regular file: opening it cannot block
  std::string first(4096, '\0');
  in.read(first.data(), static_cast<std::streamsize>(first.size()));
  first.resize(static_cast<std::size_t>(in.gcount()));
  const std::size_t eol = first.find('\n');
  const std::string header = first.substr(0, eol);
  if (eol == std::string::npos || (header != "t" && header.rfind("t,", 0) != 0)) {
    throw ConfigError(fmt::format(
        "{} = '{}': not a run journal: expected a first line of channel names starting with "
        "t (t,q1,...), got {}; give the .csv file written by 'hybridtest run'", what, path,
        first.empty() ? std::string("an empty file")
                      : fmt::format("'{}'", header.substr(0, 60))));
  }
}

void CheckMonitorOptions(const MonitorCliOptions& options) {
  if (!std::isfinite(options.linger)) {
    throw ConfigError(fmt::format("--monitor-linger = {}: expected a finite number of seconds "
                                  "from 0 to 86400", options.linger));
  }
  if (options.enabled()) return;
  const char* alone = !options.token_file.empty() ? "--token-file"
                      : options.no_token          ? "--monitor-no-token"
                      : options.linger > 0.0      ? "--monitor-linger"
                                                  : nullptr;
  if (alone != nullptr) {
    throw ConfigError(fmt::format("{} is an option of the live monitor, which is not served: "
                                  "add --monitor HOST:PORT (e.g. --monitor 127.0.0.1:8080), or "
                                  "remove {}", alone, alone));
  }
}

}  // namespace hybridtest::app
