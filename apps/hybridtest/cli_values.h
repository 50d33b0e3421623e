#pragma once
// Parsing of numeric command-line values ("0.1,0.2,0.3"), with errors naming the option.
#include <string>
#include <vector>

namespace hybridtest::app {

// Splits a comma-separated list of finite numbers. Throws ConfigError naming `option`.
std::vector<double> ParseNumberList(const std::string& text, const std::string& option);

}  // namespace hybridtest::app
