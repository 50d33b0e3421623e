// Issue 33, items 8 and 9: every number that sizes a loop or an allocation is bounded, every
// input file must be a regular file, and input that used to be silently accepted (or refused
// with an uncaught YAML exception) is a ConfigError naming the key and the fix.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>

#include "hybridtest/common/error.h"
#include "hybridtest/common/input_file.h"
#include "hybridtest/io/config.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/io/substructure_config.h"
#include "support/temp_dir.h"

namespace hybridtest::io {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

// The message of the ConfigError that compiling `text` throws (as `run` does: the config, the
// substructures, real time), or "(no error)".
std::string ErrorOf(const std::string& text, const SubstructureOptions& options = {}) {
  try {
    CompileRunSpec(ParseSimulationConfig(YamlInput::FromText(text, "cfg.yaml")), options);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

const std::string kRotor =
    "model: {name: rotor, blades: 3}\nintegrator: {tableau: heun, dt: 0.001}\nduration: 0.01\n";

// A physical slot r1 on the emulated real-time plant, with `transfer` as given.
std::string RtPlant(const std::string& transfer) {
  return "model: {name: rotor, blades: 3}\n"
         "integrator: {scheme: alpha-os, dt: 0.001}\nduration: 0.01\n"
         "substructures:\n  r1:\n    type: physical\n    initial_stiffness: 7200\n"
         "    transfer: " + transfer + "\n    safety: defaults\n";
}
const std::string kPlant = "{type: rt_plant, plant: servo_hydraulic, specimen: {mass: 29.13, "
                           "stiffness: 1.19e6, zeta: 0.0097}";

TEST(ConfigInputBounds, PlantRateDelayAndWindowAreBounded) {
  EXPECT_EQ(ErrorOf(RtPlant(kPlant + "}")), "(no error)");
  EXPECT_THAT(ErrorOf(RtPlant(kPlant + ", rate_hz: 1e12}")),
              AllOf(HasSubstr("substructures.r1.transfer.rate_hz"), HasSubstr("1e12"),
                    HasSubstr("from 1 to 1e+06")));
  EXPECT_THAT(ErrorOf(RtPlant(kPlant + ", rate_hz: 0.5}")), HasSubstr("rate_hz"));
  EXPECT_EQ(ErrorOf(RtPlant(kPlant + ", rate_hz: 1e6}")), "(no error)");
  EXPECT_THAT(ErrorOf(RtPlant(kPlant + ", delay: 1e12}")),
              AllOf(HasSubstr("substructures.r1.transfer.delay"), HasSubstr("from 0 to 1")));
  const std::string compensated = "{type: compensated, method: ats, window: 1e12, inner: " +
                                  kPlant + "}}";
  EXPECT_THAT(ErrorOf(RtPlant(compensated)),
              AllOf(HasSubstr("substructures.r1.transfer.window"), HasSubstr("to 10")));
  EXPECT_THAT(ErrorOf(RtPlant("{type: compensated, method: polynomial, delay: 1e9, inner: " +
                              kPlant + "}}")),
              HasSubstr("substructures.r1.transfer.delay"));
}

TEST(ConfigInputBounds, ARealTimeTickIsAtLeastTenMicroseconds) {
  const std::string numerical = "model: {name: rotor, blades: 3}\nduration: 0.001\n";
  EXPECT_THAT(ErrorOf(numerical + "integrator: {tableau: heun, dt: 1e-9}\nreal_time: true\n"),
              AllOf(HasSubstr("integrator.dt"), HasSubstr("at least 1e-05 s")));
  EXPECT_THAT(ErrorOf(numerical + "integrator: {tableau: heun, dt: 1e-7}\n"
                      "real_time: {hold_after_misses: 0}\n"),
              HasSubstr("integrator.dt"));
  EXPECT_EQ(ErrorOf(numerical + "integrator: {tableau: heun, dt: 0.0001}\nreal_time: true\n"),
            "(no error)");
}

TEST(ConfigInputBounds, EveryListOfAFileIsBoundedWhereItIsParsed) {
  // A list no reader checks itself (test: is free-form) is refused as well, with its key.
  std::string list = "test: {serials: [";
  for (std::size_t i = 0; i <= kMaxListLength; ++i) list += "0,";
  list += "0]}\n";
  EXPECT_THAT(ErrorOf(kRotor + list),
              AllOf(HasSubstr("cfg.yaml:4: test.serials"), HasSubstr("100002 entries"),
                    HasSubstr("at most 100000")));
  std::string exact = "test: {serials: [0";
  for (std::size_t i = 1; i < kMaxListLength; ++i) exact += ",0";
  exact += "]}\n";
  EXPECT_EQ(ErrorOf(kRotor + exact), "(no error)");
}

TEST(ConfigInputBounds, ProgressQuietIsTrueOrFalse) {
  EXPECT_THAT(ErrorOf(kRotor + "progress: {quiet: maybe}\n"),
              AllOf(HasSubstr("cfg.yaml:4: progress.quiet = 'maybe'"), HasSubstr("true or false")));
  EXPECT_THAT(ErrorOf(kRotor + "progress: {quiet: [1]}\n"), HasSubstr("progress.quiet"));
  EXPECT_TRUE(ParseSimulationConfig(YamlInput::FromText(kRotor + "progress: {quiet: true}\n",
                                                         "cfg.yaml")).quiet);
  EXPECT_FALSE(ParseSimulationConfig(YamlInput::FromText(kRotor + "progress: {quiet: false}\n",
                                                          "cfg.yaml")).quiet);
}

TEST(ConfigInputBounds, NumericalSlotsRefuseThePhysicalKeys) {
  const std::string slot = kRotor + "substructures:\n  r1:\n    type: numerical\n";
  EXPECT_THAT(ErrorOf(slot + "    safety: {stroke_max: 0.1}\n"),
              AllOf(HasSubstr("substructures.r1.safety"), HasSubstr("type: physical"),
                    HasSubstr("remove it")));
  EXPECT_THAT(ErrorOf(slot + "    initial_stiffness: measure\n"),
              AllOf(HasSubstr("substructures.r1.initial_stiffness"), HasSubstr("remove it")));
  EXPECT_THAT(ErrorOf(slot + "    transfer: {type: loopback}\n"),
              HasSubstr("substructures.r1.transfer"));
  EXPECT_THAT(ErrorOf(slot + "    setup: {p0: 0.02}\n"), HasSubstr("substructures.r1.setup"));
  EXPECT_EQ(ErrorOf(slot + "    law: {type: linear, stiffness: 7200}\n"), "(no error)");
}

TEST(ConfigInputBounds, BenchAddressNeedsANetworkedSlot) {
  SubstructureOptions with_bench;
  with_bench.bench_address = "127.0.0.1:7471";
  // No physical slot at all, then only an in-process one: --bench would be ignored.
  EXPECT_THAT(ErrorOf(kRotor, with_bench),
              AllOf(HasSubstr("--bench 127.0.0.1:7471"), HasSubstr("remove --bench")));
  const std::string loopback =
      kRotor + "substructures:\n  r1:\n    type: physical\n"
               "    transfer: {type: loopback, law: {type: linear, stiffness: 7200}}\n"
               "    safety: defaults\n";
  EXPECT_THAT(ErrorOf(loopback, with_bench), HasSubstr("--bench"));
  EXPECT_EQ(ErrorOf(loopback), "(no error)");
  // A remote slot takes it.
  const std::string remote =
      kRotor + "substructures:\n  r1:\n    type: physical\n    transfer: {type: remote}\n"
               "    setup: {p0: 0.02}\n    safety: defaults\n";
  EXPECT_EQ(ErrorOf(remote, with_bench), "(no error)");
}

TEST(ConfigInputBounds, UserTableauWithoutANamesTheKey) {
  const std::string head = "model: {name: double_pendulum}\nduration: 1\n";
  const std::string without_a = head +
      "integrator:\n  tableau: {name: mine, b: [0.5, 0.5], c: [0, 1], order: 2}\n  dt: 0.01\n";
  EXPECT_THAT(ErrorOf(without_a), AllOf(HasSubstr("integrator.tableau.a"), HasSubstr("missing"),
                                        HasSubstr("add `a:`")));
  EXPECT_THAT(ErrorOf(head + "integrator:\n  tableau: {b: [1], c: [0], a: 5, order: 1}\n"
                             "  dt: 0.01\n"),
              HasSubstr("integrator.tableau.a"));
  EXPECT_THAT(ErrorOf(head + "integrator:\n  tableau: {b: [1, 0], c: [0], a: [[0, 0], [1, 0]], "
                             "order: 1}\n  dt: 0.01\n"),
              HasSubstr("c 1 entries"));
  std::string many = "[1";
  for (int i = 1; i < 65; ++i) many += ",0";
  many += "]";
  EXPECT_THAT(ErrorOf(head + "integrator:\n  tableau: {b: " + many + ", c: " + many +
                      ", a: [], order: 1}\n  dt: 0.01\n"),
              AllOf(HasSubstr("integrator.tableau.b"), HasSubstr("1 to 64")));
}

TEST(ConfigInputBounds, FuzzCorpusInputOfTheTableauCrashIsAConfigError) {
  // The seed the fuzz target keeps for this crash, through the loader the target calls.
  const std::string seed =
      std::string(HYBRIDTEST_SOURCE_DIR) + "/fuzz/corpus/run_config/user_tableau_without_a.yaml";
  try {
    const SimulationConfig cfg = ParseSimulationConfig(YamlInput::FromFile(seed));
    MakeSubstructures(cfg, {});
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr("integrator.tableau.a"));
  }
}

class InputFileTest : public ::testing::Test {
 protected:
  std::filesystem::path dir_ = test_support::FreshTempDir("input_file");
  void TearDown() override { std::filesystem::remove_all(dir_); }
};

std::string ReadError(const std::string& path, std::size_t max_bytes = 1000) {
  try {
    ReadInputFile(path, "--token-file", "token file", max_bytes);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST_F(InputFileTest, OnlyRegularFilesAreReadAndNothingBlocks) {
  const std::string fifo = (dir_ / "token").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const auto start = std::chrono::steady_clock::now();
  EXPECT_THAT(ReadError(fifo), AllOf(HasSubstr("--token-file = '" + fifo + "'"),
                                     HasSubstr("not a regular file (a FIFO)"),
                                     HasSubstr("give a token file here")));
  RecordProperty("fifo_refusal_ms",
                 static_cast<int>(std::chrono::duration_cast<std::chrono::milliseconds>(
                                      std::chrono::steady_clock::now() - start).count()));
  EXPECT_EQ(RegularFileProblem(fifo), "a FIFO");
  EXPECT_THAT(ReadError(dir_.string()), HasSubstr("(a directory)"));
  EXPECT_THAT(ReadError("/dev/zero"), HasSubstr("(a device)"));
  EXPECT_THAT(ReadError((dir_ / "missing").string()),
              AllOf(HasSubstr("cannot open this token file (no such file)"),
                    HasSubstr("check that it exists")));
  try {
    RequireRegularFile(fifo, "", "YAML file");
    ADD_FAILURE() << "a FIFO passed RequireRegularFile";
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr(fifo + ": not a regular file (a FIFO); give a YAML file"));
  }
}

TEST_F(InputFileTest, ReadsWholeFilesUpToTheBound) {
  const std::string path = (dir_ / "t.txt").string();
  test_support::WriteText(path, std::string(1000, 'x'));
  EXPECT_EQ(ReadInputFile(path, "t", "file", 1000), std::string(1000, 'x'));
  EXPECT_THAT(ReadError(path, 999), AllOf(HasSubstr("larger than 999 bytes"),
                                          HasSubstr("the most a token file may hold")));
  test_support::WriteText(path, "");
  EXPECT_EQ(ReadInputFile(path, "t", "file", 10), "");
  // Through a symbolic link, the target is read.
  const std::string link = (dir_ / "link").string();
  test_support::WriteText(path, "abc");
  std::filesystem::create_symlink(path, link);
  EXPECT_EQ(ReadInputFile(link, "t", "file", 10), "abc");
}

}  // namespace
}  // namespace hybridtest::io
