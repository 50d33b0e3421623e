// ExportCsvWithUnits: names, a units row, values converted to lab units, NaN as empty fields;
// read back as numbers, the SI export equals the run exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include "hybridtest/common/error.h"
#include "hybridtest/report/csv_export.h"
#include "support/temp_dir.h"

namespace hybridtest::report {
namespace {

io::RunData SmallRun() {
  io::RunData run;
  run.channels = {{"t", "s", "time"}, {"q1", "m", "tip"}, {"r1", "N", "force"},
                  {"r1_force", "N", "load cell"}};
  run.values.resize(2, 4);
  run.values << 0.0, 0.0125, 3.5, std::numeric_limits<double>::quiet_NaN(),  //
      0.001, -0.1 / 3.0, 1234.5, 1.0 / 3.0;
  return run;
}

std::vector<std::string> Lines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

TEST(CsvExport, WritesNamesThenUnitsThenExactSiValues) {
  const auto dir = test_support::FreshTempDir("csv_export");
  const std::string path = (dir / "si.csv").string();
  const io::RunData run = SmallRun();
  ExportCsvWithUnits(run, path, ParsePlotUnits(""));
  const auto lines = Lines(path);
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines[0], "t,q1,r1,r1_force");
  EXPECT_EQ(lines[1], "s,m,N,N");
  EXPECT_EQ(lines[2], "0,0.0125,3.5,");  // the missing sample stays missing
  std::stringstream row(lines[3]);
  for (int c = 0; c < 4; ++c) {
    std::string field;
    std::getline(row, field, ',');
    EXPECT_EQ(std::stod(field), run.values(1, c)) << "column " << c;  // round-trips exactly
  }
}

TEST(CsvExport, ConvertsToLabUnits) {
  const auto dir = test_support::FreshTempDir("csv_export_lab");
  const std::string path = (dir / "lab.csv").string();
  ExportCsvWithUnits(SmallRun(), path, ParsePlotUnits("mm,kN"));
  const auto lines = Lines(path);
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines[1], "s,mm,kN,kN");
  EXPECT_EQ(lines[2], "0,12.5,0.0035,");
}

TEST(CsvExport, AnUnwritablePathIsNamed) {
  try {
    ExportCsvWithUnits(SmallRun(), "/nonexistent-dir/x.csv", ParsePlotUnits(""));
    FAIL() << "expected IoError";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/x.csv"), std::string::npos);
  }
}

}  // namespace
}  // namespace hybridtest::report
