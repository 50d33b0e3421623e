// The front door (runner/open_run.h): a run's record and guards come from what its compile
// read; every refusal comes before any file of the run is written and before anything moves.
#include "hybridtest/runner/open_run.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "hybridtest/common/error.h"
#include "hybridtest/io/digest.h"
#include "hybridtest/io/journal.h"
#include "hybridtest/io/run_lock.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/runner/session.h"
#include "support/small_disk.h"
#include "support/temp_dir.h"

namespace hybridtest::runner {
namespace {

namespace fs = std::filesystem;
using test_support::FreshTempDir;
using test_support::ReadText;
using test_support::WriteText;
using ::testing::AllOf;
using ::testing::HasSubstr;

const std::string kSource = HYBRIDTEST_SOURCE_DIR;

// examples/05_turbine_lab copied into dir/lab: the config, the model file and its cp.csv.
fs::path CopyTurbine(const fs::path& dir) {
  fs::copy(kSource + "/examples/05_turbine_lab", dir / "lab");
  return dir / "lab";
}

// The turbine's simulation, 10 steps of 2 ms, into csv.
io::RunSpec ShortTurbine(const fs::path& lab, const fs::path& csv) {
  io::RunSpec spec = io::LoadRunSpec((lab / "simulation.yaml").string());
  spec.scheme.duration = 0.02;
  spec.scheme.steps = io::StepCount(0.02, spec.scheme.dt);
  spec.output.csv_path = csv.string();
  spec.output.command = "simulate";
  spec.quiet = true;
  return spec;
}

std::string Listing(const fs::path& dir) {
  std::string names;
  for (const auto& entry : fs::directory_iterator(dir)) {
    names += entry.path().filename().string() + " ";
  }
  return names;
}

TEST(OpenRun, TheRecordNamesEveryFileTheCompileReadTheModelsTableIncluded) {
  const fs::path dir = FreshTempDir("open_run_record");
  const fs::path lab = CopyTurbine(dir);
  const fs::path csv = dir / "out" / "t.csv";
  io::RunSpec spec = ShortTurbine(lab, csv);
  {
    const OpenedRun opened = OpenRun(spec, {.command_line = "open_run_test"});
    EXPECT_TRUE(opened.locked());
    EXPECT_TRUE(fs::exists(io::RunLockPath(csv.string())));
    const nlohmann::json inputs = spec.source.inputs;
    ASSERT_EQ(inputs.size(), 3u) << inputs.dump();
    EXPECT_EQ(inputs[0]["path"], "../lab/simulation.yaml");
    EXPECT_EQ(inputs[1]["role"], "model");
    EXPECT_EQ(inputs[2]["role"], "table");
    EXPECT_EQ(inputs[2]["path"], "../lab/cp.csv");
    EXPECT_EQ(inputs[2]["sha256"], io::Sha256OfFile((lab / "cp.csv").string()));
    const auto& provenance = spec.source.provenance;
    EXPECT_EQ(provenance["command_line"], "open_run_test");
    EXPECT_EQ(provenance["output"], csv.string());
    EXPECT_EQ(provenance["inputs"][2]["text"], ReadText(lab / "cp.csv"));
    // The run writes that record into its sidecar.
    Session session(std::move(spec));
    ASSERT_EQ(session.Run().status, SessionStatus::kFinished);
    const auto sidecar = io::ReadSidecar(csv.string());
    EXPECT_EQ(sidecar["extra"]["inputs"], inputs);
    EXPECT_EQ(sidecar["extra"]["provenance"]["inputs"].size(), 3u);
  }
  EXPECT_FALSE(fs::exists(io::RunLockPath(csv.string())));  // released with the handle
  fs::remove_all(dir);
}

TEST(OpenRun, AnOutputOntoAnyFileTheCompileReadIsRefusedAndNothingIsWritten) {
  const fs::path dir = FreshTempDir("open_run_onto");
  const fs::path lab = CopyTurbine(dir);
  for (const char* name : {"simulation.yaml", "turbine.model.yaml", "cp.csv"}) {
    SCOPED_TRACE(name);
    const std::string before = ReadText(lab / name);
    io::RunSpec spec = ShortTurbine(lab, lab / name);
    try {
      const OpenedRun opened = OpenRun(spec, {.overwrite = true});
      ADD_FAILURE() << "opened a run onto " << name;
    } catch (const ConfigError& e) {
      EXPECT_THAT(e.what(), AllOf(HasSubstr(name), HasSubstr("a file it reads"),
                                  HasSubstr("(--overwrite does not allow this)")));
    }
    EXPECT_EQ(ReadText(lab / name), before);
    EXPECT_FALSE(fs::exists(io::RunLockPath((lab / name).string())));
    EXPECT_EQ(spec.source.inputs.size(), 0u);
  }
  fs::remove_all(dir);
}

// A resume's compile reads the files again: a table edited since the run started is named.
TEST(OpenRun, AResumeRefusesAFileChangedSinceTheRunStarted) {
  const fs::path dir = FreshTempDir("open_run_resume");
  const fs::path lab = CopyTurbine(dir);
  const fs::path csv = dir / "k.csv";
  nlohmann::json record;
  {
    io::RunSpec spec = ShortTurbine(lab, csv);
    const OpenedRun opened = OpenRun(spec);
    record = spec.source.inputs;
  }
  io::RunSpec same = ShortTurbine(lab, csv);
  same.source.inputs = record;
  EXPECT_NO_THROW({ const OpenedRun opened = OpenRun(same, {.resume = true}); });
  EXPECT_EQ(same.source.inputs, record);  // a resume keeps the run's own record
  WriteText(lab / "cp.csv", ReadText(lab / "cp.csv") + "# edited\n");
  io::RunSpec edited = ShortTurbine(lab, csv);
  edited.source.inputs = record;
  try {
    const OpenedRun opened = OpenRun(edited, {.resume = true});
    ADD_FAILURE() << "resumed with an edited table";
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr("cp.csv (table file): changed since the run started"));
  }
  fs::remove_all(dir);
}

TEST(OpenRun, ARunInMemoryOpensNothing) {
  const fs::path dir = FreshTempDir("open_run_memory");
  const fs::path lab = CopyTurbine(dir);
  io::RunSpec spec = ShortTurbine(lab, lab / "cp.csv");  // never written: no files
  spec.output.files = false;
  const OpenedRun opened = OpenRun(spec);
  EXPECT_FALSE(opened.locked());
  EXPECT_TRUE(spec.source.inputs.empty());
  EXPECT_TRUE(spec.source.provenance.empty());
  EXPECT_FALSE(fs::exists(io::RunLockPath((lab / "cp.csv").string())));
  fs::remove_all(dir);
}

// On a disk of 8 MB (less than the margin kept free), the run is refused with the numbers,
// and nothing of it is left there.
TEST(OpenRun, AnOutputThatCannotFitIsRefusedWithTheNumbersAndLeavesNothing) {
  const fs::path dir = FreshTempDir("open_run_disk");
  const fs::path lab = CopyTurbine(dir);
  io::RunSpec spec = ShortTurbine(lab, dir / "disk" / "k.csv");
  const auto answer = test_support::RunOnSmallDisk(dir / "disk", 8u << 20, [&] {
    try {
      const OpenedRun opened = OpenRun(spec);
      return std::string("opened");
    } catch (const ConfigError& e) {
      return std::string(e.what()) + "\nleft: [" + Listing(dir / "disk") + "]";
    }
  });
  if (!answer) GTEST_SKIP() << "no private mount namespace here (unshare)";
  EXPECT_THAT(*answer, AllOf(HasSubstr("k.csv: this run would write about"),
                             HasSubstr("free"), HasSubstr("left: []")));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hybridtest::runner
