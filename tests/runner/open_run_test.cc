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
    OpenedRun opened = OpenRun(spec, {.command_line = "open_run_test"});
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
    Session session(std::move(spec), std::move(opened));
    ASSERT_EQ(session.Run().status, SessionStatus::kFinished);
    const auto sidecar = io::ReadSidecar(csv.string());
    EXPECT_EQ(sidecar["extra"]["inputs"], inputs);
    EXPECT_EQ(sidecar["extra"]["provenance"]["inputs"].size(), 3u);
  }
  EXPECT_FALSE(fs::exists(io::RunLockPath(csv.string())));  // released with the session
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

// A resume of csv with nothing else asked.
ResumeRequest Request(const fs::path& csv) {
  ResumeRequest request;
  request.csv = csv.string();
  return request;
}

// A run of ShortTurbine into csv, held after `steps` committed steps (resumable).
void RunHeld(const fs::path& lab, const fs::path& csv, int steps) {
  io::RunSpec spec = ShortTurbine(lab, csv);
  OpenedRun opened = OpenRun(spec);
  Session session(std::move(spec), std::move(opened));
  ASSERT_EQ(session.Initialize().status, SessionStatus::kWorking);
  for (int i = 0; i < steps; ++i) ASSERT_EQ(session.Step().status, SessionStatus::kWorking);
  session.RequestStop();
  ASSERT_EQ(session.Step().status, SessionStatus::kHeld);
}

// A resume goes through the front door as a run does (OpenResume): its lock is held from
// before the run is read until the opened resume ends, so a second resume (or a run onto the
// same journal) is refused meanwhile; its compile reads the files again, and a table edited
// since the run started is named.
TEST(OpenRun, AResumeIsOpenedThroughTheFrontDoorAndRefusesAFileChangedSinceTheRunStarted) {
  const fs::path dir = FreshTempDir("open_run_resume");
  const fs::path lab = CopyTurbine(dir);
  const fs::path csv = dir / "k.csv";
  RunHeld(lab, csv, 3);
  {
    std::vector<std::string> planned;
    const OpenedResume resume = OpenResume(
        {.request = Request(csv),
         .command_line = "test",
         .planned = [&](const ResumePlan& plan) { planned.push_back(plan.previous_status); }});
    EXPECT_TRUE(resume.opened.locked());
    EXPECT_EQ(planned.size(), 1u);  // told the plan once, before the compile
    EXPECT_EQ(resume.setup.spec.output.csv_path, csv.string());
    EXPECT_EQ(resume.setup.spec.output.command, "simulate");
    EXPECT_EQ(resume.setup.spec.source.inputs, resume.plan.state.inputs);  // its own record
    EXPECT_FALSE(resume.plan.state.inputs.empty());
    // The lock is the opened resume's: another resume of the run is refused while it lives.
    try {
      const OpenedResume second = OpenResume({.request = Request(csv)});
      ADD_FAILURE() << "a second resume opened the run";
    } catch (const ConfigError& e) {
      EXPECT_THAT(e.what(), HasSubstr(csv.filename().string()));
    }
    io::RunSpec again = ShortTurbine(lab, csv);
    EXPECT_THROW({ const OpenedRun opened = OpenRun(again, {.overwrite = true}); }, ConfigError);
  }
  WriteText(lab / "cp.csv", ReadText(lab / "cp.csv") + "# edited\n");
  try {
    const OpenedResume resume = OpenResume({.request = Request(csv)});
    ADD_FAILURE() << "resumed with an edited table";
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr("cp.csv (table file): changed since the run started"));
  }
  EXPECT_FALSE(fs::exists(io::RunLockPath(csv.string())));  // released on the refusal
  try {
    const OpenedResume resume = OpenResume({.request = Request(dir / "none.csv")});
    ADD_FAILURE() << "resumed a journal that does not exist";
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr("none.csv: no such journal"));
  }
  fs::remove_all(dir);
}

// No run writes its files but through the front door: a file-backed Session is made only from
// the OpenedRun of its own journal, and holds its lock until it is destroyed. Refused, nothing
// of the run is written and an OpenedRun handed in is released.
TEST(OpenRun, AFileBackedSessionIsMadeOnlyFromTheRunOpenedForItsJournal) {
  const fs::path dir = FreshTempDir("open_run_session");
  const fs::path lab = CopyTurbine(dir);
  const io::RunSpec spec = ShortTurbine(lab, dir / "a.csv");
  try {
    Session session(spec);
    ADD_FAILURE() << "a session wrote a run that was not opened";
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), AllOf(HasSubstr("a.csv"), HasSubstr("runner::OpenRun(spec)"),
                                HasSubstr("output.files = false")));
  }
  io::RunSpec other = ShortTurbine(lab, dir / "b.csv");
  OpenedRun opened_b = OpenRun(other);
  try {
    Session session(spec, std::move(opened_b));
    ADD_FAILURE() << "a session wrote its run under another run's lock";
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), AllOf(HasSubstr("a.csv"), HasSubstr("opened for"), HasSubstr("b.csv")));
  }
  EXPECT_FALSE(fs::exists(io::RunLockPath((dir / "b.csv").string())));  // released
  EXPECT_FALSE(fs::exists(dir / "a.csv"));
  {
    io::RunSpec run = spec;
    OpenedRun opened = OpenRun(run);
    Session session(std::move(run), std::move(opened));
    EXPECT_TRUE(fs::exists(io::RunLockPath((dir / "a.csv").string())));  // the session's
  }
  EXPECT_FALSE(fs::exists(io::RunLockPath((dir / "a.csv").string())));
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
