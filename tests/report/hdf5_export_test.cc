// ExportHdf5, checked by an independent reader: a Python script using h5py and Python's own
// CSV and JSON parsers (check_hdf5_export.py), run with Debian's /usr/bin/python3.
#include "hybridtest/report/hdf5_export.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "hybridtest/common/error.h"
#include "hybridtest/io/journal.h"
#include "hybridtest/io/run_reader.h"

namespace hybridtest::report {
namespace {

namespace fs = std::filesystem;

constexpr const char* kPython = "/usr/bin/python3";

std::string TempDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() /
                       ("hybridtest_hdf5_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

bool HaveH5py() {
  return std::system((std::string(kPython) + " -c 'import h5py' 2>/dev/null").c_str()) == 0;
}

// Runs the checker; returns its exit status and lets its output go to the test log.
int RunChecker(const std::string& h5, const std::string& csv, const std::string& sidecar) {
  const std::string command = std::string(kPython) + " '" + HYBRIDTEST_SOURCE_DIR +
                              "/tests/report/check_hdf5_export.py' '" + h5 + "' '" + csv +
                              "'" + (sidecar.empty() ? "" : " '" + sidecar + "'");
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// A run shaped like a hybrid test of the rotor: 4 DOF, 3 slots, r1 physical, plus an extra.
std::string WriteHybridRun(const std::string& dir, int rows) {
  std::vector<io::Channel> channels = {{"t", "s", "simulated time"}};
  for (int i = 1; i <= 4; ++i) {
    channels.push_back({"q" + std::to_string(i), i == 4 ? "rad" : "m", "coordinate"});
  }
  for (int i = 1; i <= 4; ++i) {
    channels.push_back({"u" + std::to_string(i), i == 4 ? "rad/s" : "m/s", "speed"});
  }
  for (int i = 1; i <= 3; ++i) channels.push_back({"r" + std::to_string(i), "N", "blade force"});
  channels.push_back({"r1_command", "m", "actuator command, q1 + p0"});
  channels.push_back({"r1_position", "m", "measured actuator position"});
  channels.push_back({"r1_force", "N", "measured force (ünïcode ok)"});
  channels.push_back({"r1_lab_time", "s", "lab time"});
  channels.push_back({"kinetic_energy", "J", "kinetic energy"});
  io::JournalMetadata metadata;
  metadata.command = "run";
  metadata.config_path = "examples/hybrid.yaml";
  metadata.config_text = "model: rotor\n# a comment, with \"quotes\"\n";
  const std::string csv = dir + "/run.csv";
  io::Journal journal(csv, channels, metadata, io::SyncPolicy::kBatched, 64);
  std::vector<double> row(channels.size());
  for (int k = 0; k < rows; ++k) {
    for (std::size_t j = 0; j < row.size(); ++j) {
      row[j] = std::sin(0.37 * k + 1.3 * static_cast<double>(j)) * std::pow(10.0, j % 7 - 3);
    }
    row[0] = 1e-3 * k;
    journal.Append(row);
  }
  journal.Finish({{"steps", rows}}, "completed");
  return csv;
}

TEST(Hdf5Export, DatasetPathsFollowTheLayout) {
  EXPECT_EQ(Hdf5DatasetPath("t"), "/time/t");
  EXPECT_EQ(Hdf5DatasetPath("q3"), "/coordinates/q3");
  EXPECT_EQ(Hdf5DatasetPath("u1"), "/speeds/u1");
  EXPECT_EQ(Hdf5DatasetPath("r2"), "/restoring_forces/r2");
  EXPECT_EQ(Hdf5DatasetPath("r1_lab_time"), "/physical/r1/lab_time");
  EXPECT_EQ(Hdf5DatasetPath("energy"), "/other/energy");
  EXPECT_EQ(Hdf5DatasetPath("a/b"), "/other/a_b");
}

TEST(Hdf5Export, IndependentReaderSeesValuesAndUnits) {
  if (!HaveH5py()) GTEST_SKIP() << "python3-h5py is not installed";
  const std::string dir = TempDir("hybrid");
  const std::string csv = WriteHybridRun(dir, 2500);
  const io::RunData run = io::LoadRun(csv);
  ExportHdf5(run, dir + "/run.h5");
  EXPECT_EQ(RunChecker(dir + "/run.h5", csv, io::SidecarPath(csv)), 0);
}

TEST(Hdf5Export, CheckerCatchesACorruptedExport) {
  // The oracle must be able to fail: export a run whose values were altered after loading.
  if (!HaveH5py()) GTEST_SKIP() << "python3-h5py is not installed";
  const std::string dir = TempDir("corrupt");
  const std::string csv = WriteHybridRun(dir, 10);
  io::RunData run = io::LoadRun(csv);
  run.values(7, 3) = std::nextafter(run.values(7, 3), 1e9);
  ExportHdf5(run, dir + "/run.h5");
  EXPECT_EQ(RunChecker(dir + "/run.h5", csv, io::SidecarPath(csv)), 1);
  run = io::LoadRun(csv);
  run.channels[5].unit = "mm";
  ExportHdf5(run, dir + "/run.h5");
  EXPECT_EQ(RunChecker(dir + "/run.h5", csv, io::SidecarPath(csv)), 1);
}

TEST(Hdf5Export, RunWithoutSidecarAndWithoutRows) {
  if (!HaveH5py()) GTEST_SKIP() << "python3-h5py is not installed";
  const std::string dir = TempDir("bare");
  std::ofstream(dir + "/bare.csv") << "t,q1,r1_force,x\n";
  ExportHdf5(io::LoadRun(dir + "/bare.csv"), dir + "/bare.h5");
  EXPECT_EQ(RunChecker(dir + "/bare.h5", dir + "/bare.csv", ""), 0);
  std::ofstream(dir + "/small.csv") << "t,q1,r1_force,x\n0,1,2,3\n0.5,nan,-inf,1e-300\n";
  ExportHdf5(io::LoadRun(dir + "/small.csv"), dir + "/small.h5");
  EXPECT_EQ(RunChecker(dir + "/small.h5", dir + "/small.csv", ""), 0);
}

// The provenance a lab signs (a test block, host, command line, inputs with their text and
// sha256: whatever keys the sidecar holds) becomes root attributes; the stage record joins.
TEST(Hdf5Export, SidecarProvenanceBecomesRootAttributesAndStagesJoin) {
  if (!HaveH5py()) GTEST_SKIP() << "python3-h5py is not installed";
  const std::string dir = TempDir("provenance");
  const std::string csv = WriteHybridRun(dir, 30);
  nlohmann::json sidecar = io::ReadSidecar(csv);
  sidecar["test"] = {{"specimen", "S-0421"}, {"operator", "A. Lab"}, {"notes", "first article"},
                     {"batch", 7}, {"witnessed", true}};
  sidecar["host"] = "rig-3";
  sidecar["command_line"] = {"hybridtest", "run", "x.yaml", "--out", "r/run.csv"};
  const std::string long_text(100000, 'y');  // beyond an object header's 64 KiB
  sidecar["inputs"] = {{{"role", "config"}, {"sha256", std::string(64, 'a')}, {"text", long_text}},
                       {{"role", "bench"}, {"sha256", std::string(64, 'b')}, {"text", ""}}};
  sidecar["limits_m"] = {-0.1, 0.1};
  sidecar["unset"] = nullptr;
  std::ofstream(io::SidecarPath(csv)) << sidecar.dump(2);
  std::ofstream(dir + "/run.stages.csv")
      << "step,stage,t,r1_command,r1_position,r1_force,r1_lab_time\n"
         "0,0,0,0.1,0.1,1.5,0\n0,1,0.0005,0.1001,0.1001,1.75,1.13\n1,0,0.001,0.1002,0.1002,2,2.26\n";
  ExportHdf5(io::LoadRun(csv), dir + "/run.h5");
  EXPECT_EQ(RunChecker(dir + "/run.h5", csv, io::SidecarPath(csv)), 0);
  // The checker fails on a provenance the file does not carry.
  sidecar["test"]["specimen"] = "S-0422";
  std::ofstream(dir + "/other.meta.json") << sidecar.dump(2);
  EXPECT_EQ(RunChecker(dir + "/run.h5", csv, dir + "/other.meta.json"), 1);
}

TEST(Hdf5Export, UnwritablePathIsAClearIoError) {
  const std::string dir = TempDir("error");
  std::ofstream(dir + "/run.csv") << "t\n0\n";
  const io::RunData run = io::LoadRun(dir + "/run.csv");
  try {
    ExportHdf5(run, dir + "/missing/dir/run.h5");
    FAIL() << "expected IoError";
  } catch (const IoError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("missing/dir/run.h5"), std::string::npos) << message;
    EXPECT_NE(message.find("directory exists"), std::string::npos) << message;
  }
}

TEST(Hdf5Export, CommandLineExportsBesideTheCsvOrWhereTold) {
  if (!HaveH5py()) GTEST_SKIP() << "python3-h5py is not installed";
  const std::string dir = TempDir("cli");
  const std::string csv = WriteHybridRun(dir, 50);
  const std::string binary = HYBRIDTEST_BINARY;
  ASSERT_EQ(std::system(("'" + binary + "' export '" + csv + "' --hdf5 '" + dir +
                         "/named.h5' >/dev/null")
                            .c_str()),
            0);
  EXPECT_EQ(RunChecker(dir + "/named.h5", csv, io::SidecarPath(csv)), 0);
  ASSERT_EQ(std::system(("'" + binary + "' export '" + csv + "' >/dev/null").c_str()), 0);
  EXPECT_EQ(RunChecker(dir + "/run.h5", csv, io::SidecarPath(csv)), 0);
  // A failure is a message and a non-zero status, not a crash.
  const int status = std::system(("'" + binary + "' export '" + csv + "' --hdf5 '" + dir +
                                  "/missing/x.h5' 2>/dev/null")
                                     .c_str());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 1) << status;
}

}  // namespace
}  // namespace hybridtest::report
