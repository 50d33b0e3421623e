// The files a run read, as the compile's readers report them (RunSpec::source.files), and
// their record (run_inputs.h): digests for every file but a token, never a secret's content.
#include "hybridtest/io/run_inputs.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "hybridtest/io/digest.h"
#include "hybridtest/io/run_outputs.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "support/temp_dir.h"

namespace hybridtest::io {
namespace {

namespace fs = std::filesystem;
using test_support::FreshTempDir;
using test_support::ReadText;
using test_support::WriteText;
using ::testing::HasSubstr;
using ::testing::Not;

const std::string kSource = HYBRIDTEST_SOURCE_DIR;
const std::string kRotor =
    "model: {name: rotor, blades: 3}\nintegrator: {tableau: heun, dt: 0.001}\nduration: 0.01\n";
const std::string kToken = "a-shared-secret-of-32-characters";

std::vector<std::string> Roles(const std::vector<RunInput>& files) {
  std::vector<std::string> roles;
  for (const auto& f : files) roles.push_back(f.role);
  return roles;
}

TEST(RunInputs, TheCompileReportsTheConfigAndItsBenchFiles) {
  const fs::path dir = FreshTempDir("inputs_bench");
  fs::copy_file(kSource + "/examples/rotor/bench-ideal.yaml", dir / "bench.yaml");
  WriteText(dir / "c.yaml", kRotor + "substructures:\n  r1:\n    type: physical\n"
                                     "    transfer: {type: emulated, config: bench.yaml}\n"
                                     "    setup: {p0: 0.02}\n    safety: defaults\n");
  const RunSpec spec = LoadRunSpec((dir / "c.yaml").string());
  ASSERT_EQ(spec.source.files.size(), 2u);
  EXPECT_EQ(spec.source.files[0].role, "config");
  EXPECT_EQ(spec.source.files[0].path, (dir / "c.yaml").string());
  EXPECT_EQ(spec.source.files[1].role, "bench");
  EXPECT_EQ(spec.source.files[1].path, (dir / "bench.yaml").string());
  EXPECT_EQ(RunInputFiles(spec.source.files),
            (std::vector<std::string>{(dir / "c.yaml").string(), (dir / "bench.yaml").string()}));
  // `plan --emulate`: the stand-in bench is what the compile read.
  SubstructureOptions emulate;
  emulate.emulate_bench = (dir / "bench.yaml").string();
  const RunSpec planned = LoadRunSpec((dir / "c.yaml").string(), emulate);
  EXPECT_EQ(Roles(planned.source.files), (std::vector<std::string>{"config", "bench"}));
  fs::remove_all(dir);
}

// `plan --emulate BENCH.yaml` reads the bench file as `type: emulated` does, either form: a
// bench of two actuators on one specimen stands in for the two-actuator blade's remote bench
// (it was read as a one-actuator file, whose keys refuse `actuators:`).
TEST(RunInputs, AnEmulatedStandInBenchOfTwoActuatorsIsReadAsTheRunsOwnBenchFilesAre) {
  const std::string blade = kSource + "/examples/06_blade_two_actuators/";
  SubstructureOptions emulate;
  emulate.emulate_bench = blade + "bench-2act.yaml";
  const RunSpec spec = LoadRunSpec(blade + "remote.yaml", emulate);
  EXPECT_EQ(Roles(spec.source.files), (std::vector<std::string>{"config", "model", "bench"}));
  int physical = 0;
  for (const auto& s : spec.substructures) {
    if (!s.physical) continue;
    ++physical;
    EXPECT_EQ(s.physical->transfer.type, "emulated");
    EXPECT_EQ(s.physical->transfer.make()->num_actuators(), 2);
  }
  EXPECT_EQ(physical, 1);
}

// The turbine's model file reads its Cp table from cp.csv (a copied rule that walked the YAML
// missed it): the compile reports it, and the record digests it.
TEST(RunInputs, TheModelFileAndItsCsvTablesAreReported) {
  const RunSpec spec = LoadRunSpec(kSource + "/examples/05_turbine_lab/dummy.yaml");
  ASSERT_EQ(Roles(spec.source.files), (std::vector<std::string>{"config", "model", "table"}));
  EXPECT_EQ(fs::path(spec.source.files[1].path).filename(), "turbine.model.yaml");
  EXPECT_EQ(fs::path(spec.source.files[2].path).filename(), "cp.csv");
  EXPECT_TRUE(fs::exists(spec.source.files[2].path)) << spec.source.files[2].path;
  const auto texts = ReadInputTexts(spec);
  const auto record = RecordRunInputs(texts, kSource + "/examples/05_turbine_lab/run.csv");
  ASSERT_EQ(record.size(), 3u);
  EXPECT_EQ(record[2]["role"], "table");
  EXPECT_EQ(record[2]["path"], "cp.csv");
  EXPECT_EQ(record[2]["sha256"], Sha256OfFile(spec.source.files[2].path));
  EXPECT_EQ(record[0]["sha256"], Sha256Hex(spec.source.config_text));
  const auto copies = InputTexts(texts);
  ASSERT_EQ(copies.size(), 3u);
  EXPECT_EQ(copies[2]["text"], ReadText(spec.source.files[2].path));
}

TEST(RunInputs, TokenFilesAreRecordedByPathNeverHashedOrCopied) {
  const fs::path dir = FreshTempDir("inputs_token");
  WriteText(dir / "secret.txt", kToken + "\n");
  WriteText(dir / "remote.yaml",
            kRotor + "substructures:\n  r1:\n    type: physical\n    transfer: {type: remote, "
                     "address: '127.0.0.1:1', token_file: secret.txt}\n    safety: defaults\n");
  WriteText(dir / "openfresco.yaml",
            kRotor + "substructures:\n  r1:\n    type: physical\n"
                     "    transfer: {type: openfresco, host: 127.0.0.1, port: 1, "
                     "token_file: secret.txt}\n    safety: defaults\n");
  for (const char* config : {"remote.yaml", "openfresco.yaml"}) {
    SCOPED_TRACE(config);
    const RunSpec spec = LoadRunSpec((dir / config).string());
    ASSERT_EQ(Roles(spec.source.files), (std::vector<std::string>{"config", "token"}));
    EXPECT_EQ(spec.source.files[1].path, (dir / "secret.txt").string());
    const auto texts = ReadInputTexts(spec);
    const auto record = RecordRunInputs(texts, (dir / "k.csv").string());
    EXPECT_EQ(record[1]["path"], "secret.txt");
    EXPECT_FALSE(record[1].contains("sha256"));
    const auto copies = InputTexts(texts);
    EXPECT_EQ(copies.size(), 1u);  // the config only
    EXPECT_THAT(copies.dump() + record.dump(), Not(HasSubstr(kToken)));
  }
  fs::remove_all(dir);
}

TEST(RunInputs, AResumeNamesEveryFileThatDiffersFromTheRecord) {
  const fs::path dir = FreshTempDir("inputs_resume");
  fs::copy(kSource + "/examples/05_turbine_lab", dir / "lab");
  const RunSpec spec = LoadRunSpec((dir / "lab" / "simulation.yaml").string());
  const std::string csv = (dir / "lab" / "k.csv").string();
  const auto record = RecordRunInputs(ReadInputTexts(spec), csv);
  EXPECT_NO_THROW(CheckRunInputs(record, spec, csv));
  WriteText(dir / "lab" / "cp.csv", ReadText(dir / "lab" / "cp.csv") + "# edited\n");
  try {
    CheckRunInputs(record, spec, csv);
    FAIL() << "a changed table was accepted";
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr("cp.csv (table file): changed since the run started"));
  }
  fs::remove(dir / "lab" / "cp.csv");
  try {
    CheckRunInputs(record, spec, csv);
    FAIL() << "a missing table was accepted";
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr("cp.csv (table file): missing or unreadable"));
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hybridtest::io
