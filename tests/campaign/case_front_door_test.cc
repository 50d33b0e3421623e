// A campaign's case opens its run through the front door (runner/open_run.h), as `run` does:
// the record names every file the case read (a model's csv table included), the provenance is
// the command line's, and an output that cannot fit is refused with the command line's message
// before anything runs.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "hybridtest/campaign/campaign_file.h"
#include "hybridtest/campaign/case_runner.h"
#include "hybridtest/io/journal.h"
#include "support/small_disk.h"
#include "support/temp_dir.h"

namespace hybridtest::campaign {
namespace {

namespace fs = std::filesystem;
using test_support::FreshTempDir;
using test_support::WriteText;
using ::testing::AllOf;
using ::testing::HasSubstr;

const std::string kSource = HYBRIDTEST_SOURCE_DIR;

TEST(CaseFrontDoor, ACaseRecordsEveryFileItReadAndTheCommandLinesProvenance) {
  const fs::path dir = FreshTempDir("case_front_door_record");
  fs::copy(kSource + "/examples/05_turbine_lab", dir / "lab");
  WriteText(dir / "c.yaml", "base: lab/simulation.yaml\ngrid: {duration: [0.02]}\n"
                            "metrics: [final(psi)]\nfigures: false\n");
  const Campaign c = LoadCampaign((dir / "c.yaml").string());
  const std::string out = (dir / "out").string();
  const CaseHooks hooks{.command_line = "hybridtest campaign c.yaml",
                        .provenance = {{"software", {{"mpi", "none (test)"}}}}};
  const CaseResult r = RunCase(c, 0, out, hooks, "test");
  ASSERT_EQ(r.status, "finished") << r.error;
  const auto sidecar = io::ReadSidecar(CaseJournal(out, c, 0));
  const auto& inputs = sidecar["extra"]["inputs"];
  ASSERT_EQ(inputs.size(), 3u) << inputs.dump();
  EXPECT_EQ(inputs[0]["role"], "config");
  EXPECT_EQ(inputs[0]["path"], "config.yaml");
  EXPECT_EQ(inputs[1]["role"], "model");
  EXPECT_EQ(inputs[2]["role"], "table");
  EXPECT_EQ(fs::path(inputs[2]["path"].get<std::string>()).filename(), "cp.csv");
  const auto& provenance = sidecar["extra"]["provenance"];
  EXPECT_EQ(provenance["command_line"], "hybridtest campaign c.yaml");
  EXPECT_EQ(provenance["software"]["name"], "hybridtest");
  EXPECT_EQ(provenance["software"]["mpi"], "none (test)");
  EXPECT_EQ(provenance["inputs"].size(), 3u);
  fs::remove_all(dir);
}

// On a disk of 8 MB (less than the margin a run keeps free) the case fails with the message
// `run` gives, and writes no journal.
TEST(CaseFrontDoor, ACaseWhoseOutputCannotFitFailsWithTheCommandLinesMessage) {
  const fs::path dir = FreshTempDir("case_front_door_disk");
  WriteText(dir / "base.yaml", "model: {name: rotor, blades: 3}\n"
                               "integrator: {tableau: heun, dt: 0.001}\nduration: 0.3\n");
  WriteText(dir / "c.yaml", "base: base.yaml\ngrid: {model.parameters.k_b: [7200]}\n"
                            "metrics: [final(q1)]\nfigures: false\n");
  const Campaign c = LoadCampaign((dir / "c.yaml").string());
  const std::string out = (dir / "disk" / "out").string();
  const auto answer = test_support::RunOnSmallDisk(dir / "disk", 8u << 20, [&] {
    const CaseResult r = RunCase(c, 0, out, {}, "test");
    return r.status + "\n" + r.error + "\njournal: " +
           (fs::exists(CaseJournal(out, c, 0)) ? "written" : "none");
  });
  if (!answer) GTEST_SKIP() << "no private mount namespace here (unshare)";
  EXPECT_THAT(*answer,
              AllOf(HasSubstr("failed\n"), HasSubstr("run.csv: this run would write about"),
                    HasSubstr("(journal and stage record), but"), HasSubstr("free"),
                    HasSubstr("journal: none")));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hybridtest::campaign
