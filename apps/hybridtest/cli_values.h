#pragma once
// Parsing of numeric command-line values ("0.1,0.2,0.3"), with errors naming the option.
#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace hybridtest::app {

// Splits a comma-separated list of finite numbers. Throws ConfigError naming `option`.
std::vector<double> ParseNumberList(const std::string& text, const std::string& option);

// CLI11 validators for numeric options that refuse what CLI11's own let through: NaN and
// infinities (CLI::NonNegativeNumber accepts "nan" and "inf"), and text after the number.
// The message names the option (CLI11 prefixes it) and the value. Exit status 2.
const CLI::Validator& FiniteNumber();
const CLI::Validator& PositiveFiniteNumber();
const CLI::Validator& NonNegativeFiniteNumber();

}  // namespace hybridtest::app
