#pragma once
// The CSV dialect of the journal, shared by the writer (Journal) and the reader (LoadRun):
// comma-separated, no quoting, one header line of channel names, then one line per row of
// numbers, each the shortest text that reads back to the same double (std::to_chars without a
// precision: "0.1", "1e-300", "6.02214076e+23", "inf", "nan"; independent of the C locale), so
// that every double reads back bit for bit. Files written with 17 significant digits (before
// 0.x) read the same. Lines end with '\n'.
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace hybridtest::io {

// Significant digits that always round-trip a double (the shortest form never needs more).
inline constexpr int kCsvDigits = 17;

// Appends `value` as the shortest text that reads back to it ("0.1", "-1e-300", "inf").
void AppendCsvNumber(double value, std::string& out);

// Appends one data line, "v1,v2,...,vn\n", to `out`.
void AppendCsvRow(std::span<const double> row, std::string& out);

// One data line, "v1,v2,...,vn\n".
std::string FormatCsvRow(std::span<const double> row);

// The header line, "name1,name2,...\n".
std::string FormatCsvHeader(const std::vector<std::string>& names);

// Splits a line (without its '\n'; a trailing '\r' is ignored) at commas.
std::vector<std::string_view> SplitCsvLine(std::string_view line);

// Parses one whole field as a double (leading/trailing blanks allowed); nullopt if the field
// is not exactly one number.
std::optional<double> ParseCsvNumber(std::string_view field);

// True if `name` can be a channel name: non-empty, no comma, quote, blank or control
// character.
bool IsValidChannelName(std::string_view name);

}  // namespace hybridtest::io
