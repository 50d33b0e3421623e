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

}  // namespace hybridtest::app
