#include "hybridtest/io/csv.h"

#include <charconv>
#include <system_error>

namespace hybridtest::io {

void AppendCsvNumber(double value, std::string& out) {
  char buffer[32];
  // Shortest round trip (Ryu in libstdc++): fewer digits, and faster than a fixed precision.
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

void AppendCsvRow(std::span<const double> row, std::string& out) {
  for (std::size_t i = 0; i < row.size(); ++i) {
    if (i > 0) out.push_back(',');
    AppendCsvNumber(row[i], out);
  }
  out.push_back('\n');
}

std::string FormatCsvRow(std::span<const double> row) {
  std::string line;
  AppendCsvRow(row, line);
  return line;
}

std::string FormatCsvHeader(const std::vector<std::string>& names) {
  std::string line;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i > 0) line.push_back(',');
    line += names[i];
  }
  line.push_back('\n');
  return line;
}

std::vector<std::string_view> SplitCsvLine(std::string_view line) {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    if (comma == std::string_view::npos) {
      fields.push_back(line.substr(start));
      return fields;
    }
    fields.push_back(line.substr(start, comma - start));
    start = comma + 1;
  }
}

std::optional<double> ParseCsvNumber(std::string_view field) {
  while (!field.empty() && (field.front() == ' ' || field.front() == '\t')) field.remove_prefix(1);
  while (!field.empty() && (field.back() == ' ' || field.back() == '\t')) field.remove_suffix(1);
  if (field.empty()) return std::nullopt;
  // from_chars rejects a leading '+', which %.17g never writes but a hand-edited file may hold.
  if (field.front() == '+') field.remove_prefix(1);
  double value = 0.0;
  const auto result = std::from_chars(field.data(), field.data() + field.size(), value);
  if (result.ec != std::errc() || result.ptr != field.data() + field.size()) return std::nullopt;
  return value;
}

bool IsValidChannelName(std::string_view name) {
  if (name.empty()) return false;
  for (const char c : name) {
    const auto uc = static_cast<unsigned char>(c);
    if (uc <= ' ' || c == ',' || c == '"' || c == '\'' || uc == 0x7f) return false;
  }
  return true;
}

}  // namespace hybridtest::io
