// See csv_export.h.
#include "hybridtest/report/csv_export.h"

#include <fmt/core.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>

#include "hybridtest/common/error.h"

namespace hybridtest::report {
namespace {

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

// A field as CSV: quoted when it holds a comma, a quote or a line break.
std::string Field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

}  // namespace

void ExportCsvWithUnits(const io::RunData& run, const std::string& path, const PlotUnits& units) {
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "w"));
  if (!file) {
    throw IoError(fmt::format("{}: cannot write the CSV export: {}", path, std::strerror(errno)));
  }
  std::string names, unit_row;
  std::vector<double> factor;
  for (int c = 0; c < run.num_channels(); ++c) {
    const std::string recorded = run.Unit(run.channels[static_cast<std::size_t>(c)].name);
    if (c > 0) {  // (not `(c ? "," : "") + ...`: GCC 12 warns -Wrestrict there)
      names.push_back(',');
      unit_row.push_back(',');
    }
    names += Field(run.channels[static_cast<std::size_t>(c)].name);
    unit_row += Field(units.Label(recorded));
    factor.push_back(units.Factor(recorded));
  }
  std::string text = names + "\n" + unit_row + "\n";
  for (long k = 0; k < run.num_rows(); ++k) {
    for (int c = 0; c < run.num_channels(); ++c) {
      if (c) text += ',';
      const double v = run.values(k, c);
      if (!std::isnan(v)) text += fmt::format("{}", v * factor[static_cast<std::size_t>(c)]);
    }
    text += '\n';
    if (text.size() > (1u << 20)) {
      if (std::fwrite(text.data(), 1, text.size(), file.get()) != text.size()) break;
      text.clear();
    }
  }
  const bool ok = std::fwrite(text.data(), 1, text.size(), file.get()) == text.size() &&
                  std::fflush(file.get()) == 0;
  if (!ok) {
    throw IoError(fmt::format("{}: writing the CSV export failed: {}", path, std::strerror(errno)));
  }
}

}  // namespace hybridtest::report
