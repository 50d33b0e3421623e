// What a run's record says and where it points: the `test:` block and the provenance in the
// sidecar (software, git, host, command line, every input verbatim with its sha256), a killed
// run that is offered `hybridtest resume` (never --overwrite first), and a limit changed on
// resume with --set, recorded in the sidecar.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <fstream>

#include "hybridtest/io/digest.h"
#include "integration/child_process.h"
#include "integration/resume_support.h"
#include "support/temp_dir.h"

namespace hybridtest::testing {
namespace {

// examples/rotor/emulated-fast.yaml with the bench file named absolutely, the runner's force
// limits replaced, and a `test:` block.
fs::path WriteConfig(const fs::path& dir, double force_soft, double force_hard) {
  std::string text = test_support::ReadText(kSource + "/examples/rotor/emulated-fast.yaml");
  auto replace = [&](const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  };
  replace("config: bench-cantilever.yaml", "config: " + kSource + "/examples/rotor/bench-cantilever.yaml");
  replace("force_soft: 250", fmt::format("force_soft: {}", force_soft));
  replace("force_hard: 300", fmt::format("force_hard: {}", force_hard));
  text += "test: {specimen: \"S-0421\", operator: \"A. Lab\", notes: \"first article\"}\n";
  const fs::path config = dir / "config.yaml";
  std::ofstream(config) << text;
  return config;
}

TEST(RunRecord, TheSidecarHoldsTheTestBlockAndTheProvenance) {
  const fs::path dir = ResumeTestDir("record");
  const fs::path config = WriteConfig(dir, 250, 300);
  const fs::path csv = dir / "run.csv";
  ASSERT_EQ(RunToEnd(RunArgs(config.string(), csv), dir / "run.log"), 0);
  const nlohmann::json extra = Sidecar(csv)["extra"];
  EXPECT_EQ(extra["test"]["specimen"], "S-0421");
  EXPECT_EQ(extra["test"]["operator"], "A. Lab");
  EXPECT_EQ(extra["test"]["notes"], "first article");
  const nlohmann::json& p = extra["provenance"];
  EXPECT_FALSE(p["software"]["git"].get<std::string>().empty());
  EXPECT_FALSE(p["software"]["build_type"].get<std::string>().empty());
  EXPECT_FALSE(p["host"].get<std::string>().empty());
  EXPECT_NE(p["command_line"].get<std::string>().find("run " + config.string()), std::string::npos);
  EXPECT_EQ(p["output"], csv.string());
  // The config and the bench file, verbatim and with the sha256 of that text.
  std::map<std::string, nlohmann::json> inputs;
  for (const auto& i : p["inputs"]) inputs[i["role"].get<std::string>()] = i;
  ASSERT_TRUE(inputs.count("config") && inputs.count("bench")) << p["inputs"].dump();
  for (const char* role : {"config", "bench"}) {
    const std::string path = inputs[role]["path"].get<std::string>();
    const std::string text = test_support::ReadText(path);
    EXPECT_EQ(inputs[role]["text"], text) << role;
    EXPECT_EQ(inputs[role]["sha256"], io::Sha256Hex(text)) << role;
  }
  fs::remove_all(dir);
}

TEST(RunRecord, AKilledRunIsOfferedResumeNotOverwrite) {
  const fs::path dir = ResumeTestDir("killed_offer");
  const std::string config = kSource + "/examples/rotor/emulated.yaml";
  const fs::path csv = dir / "F.csv";
  ASSERT_TRUE(RunAndSignalAt(RunArgs(config, csv), csv, 2000, SIGKILL, dir / "run.log",
                             128 + SIGKILL));
  Child again(HybridtestArgv(RunArgs(config, csv)), dir / "again.log");
  EXPECT_EQ(again.WaitExit(60.0), 2) << again.output();
  const std::string out = again.output();
  const auto resume = out.find("hybridtest resume " + csv.string());
  ASSERT_NE(resume, std::string::npos) << out;
  EXPECT_NE(out.find("killed"), std::string::npos) << out;
  const auto overwrite = out.find("--overwrite");
  EXPECT_TRUE(overwrite == std::string::npos || overwrite > resume) << out;
  fs::remove_all(dir);
}

TEST(RunRecord, ResumeSetChangesALimitAndTheSidecarListsIt) {
  const fs::path dir = ResumeTestDir("resume_set");
  // A 100 N hard limit stops the test (its peak force is about 120 N).
  const fs::path config = WriteConfig(dir, 90, 100);
  const fs::path csv = dir / "run.csv";
  {
    Child run(HybridtestArgv(RunArgs(config.string(), csv)), dir / "run.log");
    ASSERT_EQ(run.WaitExit(120.0), 3) << run.output();
    EXPECT_NE(run.output().find("hybridtest resume " + csv.string() + " --after-safety-stop"),
              std::string::npos) << run.output();
  }
  // A soft limit above the hard one is refused, naming the setting.
  auto [bad, bad_out] = Resume(csv, {"--after-safety-stop", "--set",
                                     "substructures.r1.safety.force_soft=250"},
                               dir / "bad.log");
  EXPECT_EQ(bad, 2) << bad_out;
  EXPECT_NE(bad_out.find("--set substructures.r1.safety.force_soft=250"), std::string::npos)
      << bad_out;
  const auto [status, out] = Resume(
      csv, {"--after-safety-stop", "--set", "substructures.r1.safety.force_hard=300", "--set",
            "substructures.r1.safety.force_soft=250"},
      dir / "resume.log");
  ASSERT_EQ(status, 0) << out;
  const nlohmann::json sidecar = Sidecar(csv);
  EXPECT_EQ(sidecar["status"], "completed");
  const nlohmann::json& changes = sidecar["resumes"].back()["changes"];
  ASSERT_EQ(changes.size(), 2u) << sidecar["resumes"].dump();
  EXPECT_EQ(changes[0]["key"], "substructures.r1.safety.force_hard");
  EXPECT_EQ(changes[0]["from"], 100.0);
  EXPECT_EQ(changes[0]["to"], 300.0);
  EXPECT_EQ(changes[1]["key"], "substructures.r1.safety.force_soft");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hybridtest::testing
