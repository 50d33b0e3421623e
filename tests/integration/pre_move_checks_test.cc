// Checks before anything moves, through the real binary: a p0 or limit that disagrees with
// what the bench announces is refused with exit 2 before the bench sees a command (the run
// leaves no file behind), and `hybridtest probe` reads position, force and status without
// moving (the Modbus controller logs every command it receives: none).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "support/run_command.h"
#include "support/temp_dir.h"
#include "transfer/modbus_server_process.h"

namespace hybridtest {
namespace {

namespace fs = std::filesystem;
const std::string kSource = HYBRIDTEST_SOURCE_DIR;

std::string Slurp(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

fs::path TempDir() {
  static const fs::path dir = test_support::FreshTempDir("pre_move");
  return dir;
}

std::pair<int, std::string> Hybridtest(const std::string& args) {
  return testing::RunCommand(std::string(HYBRIDTEST_BINARY) + " " + args, 120);
}

// examples/rotor/emulated.yaml and its bench in `dir`, with text replaced in each.
fs::path EmulatedCopy(const std::string& name, const std::string& bench_from,
                      const std::string& bench_to, const std::string& run_from = "",
                      const std::string& run_to = "") {
  const fs::path dir = TempDir() / name;
  fs::create_directories(dir);
  std::string bench = Slurp(kSource + "/examples/rotor/bench-cantilever.yaml");
  std::string run = Slurp(kSource + "/examples/rotor/emulated.yaml");
  EXPECT_NE(bench.find(bench_from), std::string::npos) << bench_from;
  bench = std::regex_replace(bench, std::regex(bench_from), bench_to);
  if (!run_from.empty()) {
    EXPECT_NE(run.find(run_from), std::string::npos) << run_from;
    run = std::regex_replace(run, std::regex(run_from), run_to);
  }
  std::ofstream(dir / "bench-cantilever.yaml") << bench;
  std::ofstream(dir / "emulated.yaml") << run;
  return dir;
}

TEST(PreMoveChecks, BenchP0Of35MmAgainstSetupP0OfZeroIsRefusedBeforeAnyCommand) {
  const fs::path dir = EmulatedCopy("p0", "p0_mm: 0 ", "p0_mm: 35 ");
  const auto [status, out] =
      Hybridtest(fmt::format("run {}/emulated.yaml --out {}/out.csv", dir.string(), dir.string()));
  EXPECT_EQ(status, 2) << out;
  EXPECT_NE(out.find("substructures.r1.setup.p0 = 0 m"), std::string::npos) << out;
  EXPECT_NE(out.find("p0_mm: 35"), std::string::npos) << out;
  EXPECT_NE(out.find("setup.p0: 0.035"), std::string::npos) << out;
  EXPECT_EQ(out.find("time step"), std::string::npos) << out;
  // Nothing ran: no journal, no sidecar, no stage record.
  for (const char* file : {"out.csv", "out.meta.json", "out.stages.csv"}) {
    EXPECT_FALSE(fs::exists(dir / file)) << file;
  }
}

TEST(PreMoveChecks, P0InTheWrongUnitIsNamedAsAUnitSlip) {
  // The case: the bench's p0_mm given in m (0.035) against setup.p0 = 0.035 m.
  const fs::path dir =
      EmulatedCopy("p0_unit", "p0_mm: 0 ", "p0_mm: 0.035 ", "p0: 0.0 ", "p0: 0.035 ");
  const auto [status, out] =
      Hybridtest(fmt::format("run {}/emulated.yaml --out {}/out.csv", dir.string(), dir.string()));
  EXPECT_EQ(status, 2) << out;
  EXPECT_NE(out.find("about 1000 times"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir / "out.csv"));
}

TEST(PreMoveChecks, ForceLimitTypedInKilonewtonsIsRefused) {
  const fs::path dir = EmulatedCopy("kn", "p0_mm: 0 ", "p0_mm: 0 ", "force_soft: 250 ",
                                    "force_soft: 0.25 ");
  std::string run = Slurp(dir / "emulated.yaml");
  run = std::regex_replace(run, std::regex("force_hard: 300 "), "force_hard: 0.3 ");
  std::ofstream(dir / "emulated.yaml") << run;
  const auto [status, out] =
      Hybridtest(fmt::format("run {}/emulated.yaml --out {}/out.csv", dir.string(), dir.string()));
  EXPECT_EQ(status, 2) << out;
  EXPECT_NE(out.find("safety.force_hard = 0.3 N is about 1/1000"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir / "out.csv"));
}

TEST(PreMoveChecks, ProbeReadsTheEmulatedBenchAndFindsAMismatch) {
  const auto [ok, good] = Hybridtest("probe " + kSource + "/examples/rotor/emulated.yaml");
  EXPECT_EQ(ok, 0) << good;
  EXPECT_NE(good.find("ok: at p0, unloaded"), std::string::npos) << good;
  // The bench starts 5 mm off p0 (initial_position_mm), p0 agrees: the reading catches it.
  const fs::path dir = EmulatedCopy("probe_off", "p0_mm: 0 ", "p0_mm: 0\n  initial_position_mm: 5 ");
  const auto [bad, text] = Hybridtest(fmt::format("probe {}/emulated.yaml", dir.string()));
  EXPECT_EQ(bad, 2) << text;
  EXPECT_NE(text.find("PROBLEM: position 0.005 m"), std::string::npos) << text;
}

// A specimen on two actuators: every actuator is read and checked, and one that stands away
// from its setup.p0 is named.
TEST(PreMoveChecks, ProbeReadsEveryActuatorOfATwoActuatorSpecimen) {
  const std::string example = kSource + "/examples/06_blade_two_actuators/";
  const auto [ok, good] = Hybridtest("probe " + example + "emulated.yaml");
  EXPECT_EQ(ok, 0) << good;
  EXPECT_NE(good.find("actuator 2: position 30 mm = 0.03 m"), std::string::npos) << good;
  EXPECT_NE(good.find("ok: every actuator at p0"), std::string::npos) << good;
  const fs::path dir = TempDir() / "probe_two";
  fs::create_directories(dir);
  fs::copy_file(example + "blade_tip.yaml", dir / "blade_tip.yaml",
                fs::copy_options::overwrite_existing);
  fs::copy_file(example + "emulated.yaml", dir / "emulated.yaml",
                fs::copy_options::overwrite_existing);
  // p0 agrees, but actuator 2 starts 10 mm away from it: the reading catches it.
  const std::string bench = Slurp(example + "bench-2act.yaml");
  ASSERT_NE(bench.find("p0_mm: [20, 30]"), std::string::npos);
  std::ofstream(dir / "bench-2act.yaml")
      << std::regex_replace(bench, std::regex("p0_mm: \\[20, 30\\]"),
                            "p0_mm: [20, 30]\n  initial_position_mm: [20, 40]");
  const auto [bad, text] = Hybridtest(fmt::format("probe {}/emulated.yaml", dir.string()));
  EXPECT_EQ(bad, 2) << text;
  EXPECT_NE(text.find("PROBLEM: actuator 2: position 0.04 m"), std::string::npos) << text;
  EXPECT_EQ(text.find("PROBLEM: actuator 1"), std::string::npos) << text;
  // A setup.p0 that disagrees with the bench's p0 is refused before anything is read.
  const std::string run = Slurp(example + "emulated.yaml");
  std::ofstream(dir / "emulated.yaml")
      << std::regex_replace(run, std::regex("p0: \\[0.02, 0.03\\]"), "p0: [0.02, 0.04]");
  const auto [refused, why] = Hybridtest(fmt::format("probe {}/emulated.yaml", dir.string()));
  EXPECT_EQ(refused, 2) << why;
  EXPECT_NE(why.find("substructures.blade1.setup.p0[2] = 0.04 m, but the emulated bench "
                     "announces p0 = 0.03 m"), std::string::npos) << why;
}

TEST(PreMoveChecks, ProbeReadsAModbusControllerWithoutWritingAnything) {
  if (!testing::PymodbusAvailable()) GTEST_SKIP() << testing::kPymodbusMissing;
  const fs::path log = TempDir() / "modbus-commands.log";
  for (const char* start : {"0", "30"}) {
    SCOPED_TRACE(start);
    fs::remove(log);
    auto server = testing::ModbusServerProcess::Pymodbus(
        {"--stiffness", "5.25", "--start-mm", start, "--log-commands", log.string()});
    const auto [status, out] = Hybridtest(fmt::format(
        "probe {}/examples/rotor/modbus.yaml --bench {}", kSource, server.address()));
    if (std::string(start) == "0") {
      EXPECT_EQ(status, 0) << out;
      EXPECT_NE(out.find("status   status 0x"), std::string::npos) << out;
    } else {
      EXPECT_EQ(status, 2) << out;
      EXPECT_NE(out.find("position 30 mm = 0.03 m"), std::string::npos) << out;
      EXPECT_NE(out.find("PROBLEM: position 0.03 m"), std::string::npos) << out;
    }
    EXPECT_TRUE(!fs::exists(log) || Slurp(log).empty()) << Slurp(log);
  }
}

}  // namespace
}  // namespace hybridtest
