// See cli_values.h.
#include "cli_values.h"

#include <fmt/core.h>

#include <cmath>
#include <cstdlib>
#include <sstream>

#include "hybridtest/common/error.h"

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

}  // namespace hybridtest::app
