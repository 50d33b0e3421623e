// The summary `run` prints at the end (issue 38, item 3): durations that read as durations
// (4m01s, not "241 s = 0h04m"), lab time against simulated time as a ratio that is never
// rounded to 0x, and, for a real-time run, its deadlines as the sidecar records them.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "integration/resume_support.h"

namespace hybridtest::testing {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

std::string RunOutput(const std::vector<std::string>& args, const fs::path& log) {
  Child child(HybridtestArgv(args), log);
  EXPECT_EQ(child.WaitExit(120.0), 0) << child.output();
  return child.output();
}

TEST(RunSummary, LabTimeReadsAsADurationAndARatio) {
  const fs::path dir = ResumeTestDir("summary_lab");
  // The paper's test with MR-OS: 212 evaluations, about 4 minutes of lab time for 10 s.
  const std::string out =
      RunOutput({"run", kSource + "/examples/rotor/emulated-fast.yaml", "--out",
                 (dir / "ef.csv").string()},
                dir / "ef.log");
  const nlohmann::json stats = Sidecar(dir / "ef.csv")["statistics"];
  const double lab = stats["lab_time_s"].get<double>();
  ASSERT_GT(lab, 60.0) << stats.dump();
  EXPECT_THAT(out, HasSubstr(fmt::format("212 physical evaluations, lab time {}m{:02}s",
                                         std::lround(lab) / 60, std::lround(lab) % 60)));
  EXPECT_THAT(out, HasSubstr(fmt::format("({:.3g}x real time)", lab / 10.0)));
  EXPECT_THAT(out, Not(HasSubstr("0h0")));
  fs::remove_all(dir);
}

TEST(RunSummary, ARealTimeRunPrintsItsDeadlines) {
  const fs::path dir = ResumeTestDir("summary_rt");
  std::string config = test_support::ReadText(kSource + "/examples/real-time/storey-ats.yaml");
  const std::string model = "file: storey.model.yaml";
  config.replace(config.find(model), model.size(),
                 "file: " + kSource + "/examples/real-time/storey.model.yaml");
  test_support::WriteText(dir / "storey.yaml", config);
  const fs::path csv = dir / "storey.csv";
  const std::string out = RunOutput(
      {"run", (dir / "storey.yaml").string(), "--clock", "virtual", "--out", csv.string()},
      dir / "storey.log");
  const nlohmann::json rt = Sidecar(csv)["statistics"]["real_time"];
  EXPECT_THAT(out, HasSubstr(fmt::format("real time: {} ticks, {} missed deadlines",
                                         rt["ticks"].get<long>(), rt["misses"].get<long>())));
  EXPECT_EQ(rt["ticks"].get<long>(), 10240);
  EXPECT_THAT(out, HasSubstr("lab time 10 s (1x real time)"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hybridtest::testing
