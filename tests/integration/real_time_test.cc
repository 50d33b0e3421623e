// The real-time contract with real `hybridtest` processes (docs/real-time.md):
//   - storey-ats.yaml in virtual time exits 0, is bit-identical when repeated, and its sidecar
//     holds statistics.real_time with J1_ms, J2, J3 and the deadline statistics; it meets the
//     ATS target against storey.yaml, whose uncompensated run the stability check predicts
//     unstable (and which does go unstable: the safety limits stop it);
//   - rotor.yaml is refused with exit 2 before any command, naming both delays;
//   - the same storey-ats run paced on the wall clock records its misses and, without any,
//     exits 0 (no timing is asserted; a loaded machine's late ticks may end it on a limit).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "support/run_command.h"
#include "support/temp_dir.h"

namespace hybridtest {
namespace {

namespace fs = std::filesystem;
using testing::RunCommand;

const std::string kSource = HYBRIDTEST_SOURCE_DIR;
const std::string kBinary = HYBRIDTEST_BINARY;

std::string Slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

nlohmann::json RealTime(const fs::path& csv) {
  fs::path meta = csv;
  meta.replace_extension(".meta.json");
  return nlohmann::json::parse(Slurp(meta))["statistics"]["real_time"];
}

std::pair<int, std::string> RunHybrid(const std::string& config, const fs::path& out,
                                const std::string& clock = "virtual", int timeout = 120) {
  return RunCommand(fmt::format("{} run {} --clock {} --out {} --quiet 2>&1", kBinary, config,
                                clock, out.string()), timeout);
}

TEST(RealTime, StoreyWithAtsIsReproducibleAndMeetsTheTarget) {
  const fs::path dir = test_support::FreshTempDir("real_time_storey");
  const std::string ats = kSource + "/examples/real-time/storey-ats.yaml";
  const auto [s1, o1] = RunHybrid(ats, dir / "a.csv");
  ASSERT_EQ(s1, 0) << o1;
  const auto [s2, o2] = RunHybrid(ats, dir / "b.csv");
  ASSERT_EQ(s2, 0) << o2;
  EXPECT_EQ(Slurp(dir / "a.csv"), Slurp(dir / "b.csv"));
  const nlohmann::json rt = RealTime(dir / "a.csv");
  for (const char* key : {"J1_ms", "J2", "J3", "ticks", "misses", "overruns", "late_s",
                          "compute_s", "stability", "compensation"}) {
    EXPECT_TRUE(rt.contains(key)) << key;
  }
  EXPECT_EQ(rt["ticks"].get<long>(), 10240);
  EXPECT_EQ(rt["misses"].get<long>(), 0);
  // The uncompensated run: predicted unstable, and it is (a safety stop, exit 3).
  const auto [s3, o3] = RunHybrid(kSource + "/examples/real-time/storey.yaml", dir / "plain.csv");
  EXPECT_EQ(s3, 3) << o3;
  const nlohmann::json plain = RealTime(dir / "plain.csv");
  EXPECT_TRUE(plain["stability"][0]["unstable"].get<bool>());
  EXPECT_FALSE(rt["stability"][0]["unstable"].get<bool>());
  // The ATS target: J1 ≤ 1 ms and J2 ≤ 1/5 of the uncompensated J2.
  EXPECT_LE(rt["J1_ms"].get<double>(), 1.0);
  EXPECT_LE(rt["J2"].get<double>(), plain["J2"].get<double>() / 5.0);
  EXPECT_GE(plain["J1_ms"].get<double>(), 10.0);  // the plant's own delay shows uncompensated
}

TEST(RealTime, CompareAgainstTheReferenceStructurePrintsJ1ToJ9) {
  const fs::path dir = test_support::FreshTempDir("real_time_compare");
  const auto [s1, o1] = RunHybrid(kSource + "/examples/real-time/storey-ats.yaml", dir / "ats.csv");
  ASSERT_EQ(s1, 0) << o1;
  const auto [s2, o2] =
      RunHybrid(kSource + "/examples/real-time/storey-reference.yaml", dir / "ref.csv");
  ASSERT_EQ(s2, 0) << o2;
  const auto [s3, o3] = RunCommand(fmt::format("{} compare {} {} --out {} 2>&1", kBinary,
                                               (dir / "ats.csv").string(),
                                               (dir / "ref.csv").string(),
                                               (dir / "cmp").string()), 120);
  ASSERT_EQ(s3, 0) << o3;
  for (const char* j : {"J1 =", "J4 =", "J9 ="}) EXPECT_NE(o3.find(j), std::string::npos) << o3;
  const nlohmann::json c = nlohmann::json::parse(Slurp(dir / "cmp" / "rths_criteria.json"));
  EXPECT_EQ(c["floors"][0], "q1");
  // Compensated, the run follows its reference within a few per cent.
  for (const char* j : {"J4", "J5", "J6", "J7", "J8", "J9"}) {
    EXPECT_GT(c[j].get<double>(), 0.0) << j;
    EXPECT_LT(c[j].get<double>(), 5.0) << j;
  }
  // The reference is no real-time run of its own tracking: compared the other way round it
  // is still real time (its block), with a perfect actuator: J2 = 0.
  const auto [s4, o4] = RunCommand(fmt::format("{} compare {} {} --out {} 2>&1", kBinary,
                                               (dir / "ref.csv").string(),
                                               (dir / "ats.csv").string(),
                                               (dir / "cmp2").string()), 120);
  ASSERT_EQ(s4, 0) << o4;
  const nlohmann::json r = nlohmann::json::parse(Slurp(dir / "cmp2" / "rths_criteria.json"));
  EXPECT_NEAR(r["J2"].get<double>(), 0.0, 1e-9);
}

TEST(RealTime, RotorIsRefusedBeforeAnyCommandNamingBothDelays) {
  const fs::path dir = test_support::FreshTempDir("real_time_rotor");
  const auto [status, output] = RunHybrid(kSource + "/examples/real-time/rotor.yaml", dir / "r.csv");
  EXPECT_EQ(status, 2) << output;
  EXPECT_NE(output.find("critical delay"), std::string::npos) << output;
  EXPECT_NE(output.find("plant's delay"), std::string::npos) << output;
  EXPECT_FALSE(fs::exists(dir / "r.csv"));
}

TEST(RealTime, WallClockRunRecordsItsMisses) {
  // The same run paced on the wall clock for 10 s, with the miss policy off so that a loaded
  // machine records its misses instead of holding.
  const fs::path dir = test_support::FreshTempDir("real_time_wall");
  std::string config = Slurp(kSource + "/examples/real-time/storey-ats.yaml");
  const std::string from = "hold_after_misses: 10";
  config.replace(config.find(from), from.size(), "hold_after_misses: 0");
  config.replace(config.find("file: storey.model.yaml"), 23,
                 "file: " + kSource + "/examples/real-time/storey.model.yaml");
  std::ofstream(dir / "wall.yaml") << config;
  const auto [status, output] = RunHybrid((dir / "wall.yaml").string(), dir / "w.csv", "wall",
                                          120);
  const nlohmann::json rt = RealTime(dir / "w.csv");
  EXPECT_EQ(rt["clock"], "wall");
  ASSERT_TRUE(rt["misses"].is_number_integer());
  if (rt["misses"].get<long>() == 0) {
    // On time throughout, the run is the virtual-time run's physics: it completes.
    EXPECT_EQ(status, 0) << output;
    EXPECT_EQ(rt["ticks"].get<long>(), 10240);
  } else {
    // Late ticks let the plant run on between commands (a loaded machine): the run may end
    // on a safety limit, never otherwise.
    EXPECT_TRUE(status == 0 || status == 3) << output;
  }
  std::printf("wall clock, 1024 Hz, 10 s: misses %ld, late p50/p99/max %g/%g/%g s, compute "
              "p50/p99 %g/%g s\n", rt["misses"].get<long>(), rt["late_s"]["p50"].get<double>(),
              rt["late_s"]["p99"].get<double>(), rt["late_s"]["max"].get<double>(),
              rt["compute_s"]["p50"].get<double>(), rt["compute_s"]["p99"].get<double>());
}

}  // namespace
}  // namespace hybridtest
