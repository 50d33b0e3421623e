// The journal is the truth, and one process drives a run (issue 33, items 4 and 5): a genuine
// but older run state, and states forged with a recomputed checksum, are refused before
// anything moves (the journal and the stage record, where every bench command is recorded,
// stay byte-identical); with the run's lock file removed during a live run, `resume` is
// refused on the journal's own lock and the journal stays intact; a real-time run killed
// before it could write its state is refused with that reason.
#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <functional>

#include "hybridtest/io/run_lock.h"
#include "hybridtest/runner/run_state.h"
#include "integration/resume_support.h"

namespace hybridtest::testing {
namespace {

using ::testing::HasSubstr;

// The files a refused resume must not change.
struct RunFilesText {
  std::string journal, stages, sidecar;
  static RunFilesText Of(const fs::path& csv) {
    return {test_support::ReadText(csv),
            test_support::ReadText(fs::path(csv).replace_extension(".stages.csv")),
            test_support::ReadText(fs::path(csv).replace_extension(".meta.json"))};
  }
  bool operator==(const RunFilesText&) const = default;
};

// The emulated cantilever test (tests/data/resume-cantilever.yaml, 1 s) stopped with Ctrl-C
// once the journal holds `bytes` bytes: `run` first, then `resume`.
void StopAt(const std::vector<std::string>& args, const fs::path& csv, std::uintmax_t bytes,
            const fs::path& log) {
  ASSERT_TRUE(RunAndSignalAt(args, csv, bytes, SIGINT, log, 130)) << "the run ended first";
}

void ExpectResumeRefused(const fs::path& csv, const std::string& what) {
  const RunFilesText before = RunFilesText::Of(csv);
  const auto [status, out] = Resume(csv, {"--quiet"}, csv.parent_path() / "refused.log");
  EXPECT_EQ(status, 2) << out;
  EXPECT_THAT(out, HasSubstr(what));
  // Nothing moved: the stage record holds every bench command, the resume moves included.
  EXPECT_TRUE(RunFilesText::Of(csv) == before) << out;
}

TEST(JournalIsTruth, AnOlderGenuineStateAndForgedStatesAreRefusedBeforeAnyCommand) {
  const fs::path dir = ResumeTestDir("journal_truth");
  const fs::path csv = dir / "k.csv";
  const fs::path state = dir / "k.state.json";
  const std::string config = kSource + "/tests/data/resume-cantilever.yaml";
  StopAt(RunArgs(config, csv), csv, 20000, dir / "run.log");
  const std::string early = test_support::ReadText(state);
  ASSERT_FALSE(early.empty());
  // Continue, and stop again later.
  StopAt({"resume", csv.string(), "--quiet"}, csv, fs::file_size(csv) + 20000, dir / "r1.log");
  const std::string late = test_support::ReadText(state);
  ASSERT_NE(early, late);

  // The early state put back: genuine (its checksum is right), but older than the journal.
  test_support::WriteText(state, early);
  ExpectResumeRefused(csv, "is older than the journal");

  // Forged from the latest state, each with its checksum recomputed.
  const nlohmann::json genuine = nlohmann::json::parse(late);
  auto forge = [&](const std::function<void(nlohmann::json&)>& edit) {
    nlohmann::json j = genuine;
    edit(j);
    j["checksum"] = runner::RunStateChecksum(j);
    test_support::WriteText(state, j.dump());
  };
  const long step = genuine["scheme"]["step"].get<long>();
  for (const long k : {-5L, -1L, 1L, 5000L}) {
    forge([&](nlohmann::json& j) { j["scheme"]["step"] = step + k; });
    ExpectResumeRefused(csv, "scheme.step");
  }
  // Step and rows moved together (consistent with each other, not with the journal).
  forge([&](nlohmann::json& j) {
    j["scheme"]["step"] = step + 5000;
    j["rows"] = j["rows"].get<long>() + 5000;
  });
  ExpectResumeRefused(csv, "does not belong to this journal");
  forge([&](nlohmann::json& j) { j["statistics"]["steps"] = -1; });
  ExpectResumeRefused(csv, "statistics.steps = -1");
  forge([&](nlohmann::json& j) { j["substructures"][0]["state"]["evaluations"] = -3; });
  ExpectResumeRefused(csv, "evaluations = -3");
  forge([&](nlohmann::json& j) { j["scheme"]["t"] = j["scheme"]["t"].get<double>() + 0.5; });
  ExpectResumeRefused(csv, "is not its row");

  // The genuine latest state still resumes to the end.
  test_support::WriteText(state, late);
  const auto [status, out] = Resume(csv, {"--quiet"}, dir / "r2.log");
  EXPECT_EQ(status, 0) << out;
  EXPECT_EQ(Sidecar(csv).value("status", ""), "completed");
}

TEST(JournalIsTruth, RemovingTheLockFileOfALiveRunDoesNotLetResumeIn) {
  const fs::path dir = ResumeTestDir("journal_lock");
  // The cantilever bench paced in real time: about 30 ms per command, so the run is live for
  // the whole test (it is stopped below).
  std::string bench = test_support::ReadText(kSource + "/examples/rotor/bench-cantilever.yaml");
  for (const auto& [from, to] :
       std::vector<std::pair<std::string, std::string>>{{"pacing: accelerated", "pacing: realtime"},
                                                        {"overhead_ms: 440", "overhead_ms: 20"},
                                                        {"dwell_ms: 100", "dwell_ms: 5"},
                                                        {"window_ms: 500", "window_ms: 5"}}) {
    const auto at = bench.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    bench.replace(at, from.size(), to);
  }
  test_support::WriteText(dir / "bench.yaml", bench);
  std::string config = test_support::ReadText(kSource + "/tests/data/resume-cantilever.yaml");
  const std::string from = "../../examples/rotor/bench-cantilever.yaml";
  config.replace(config.find(from), from.size(), "bench.yaml");
  test_support::WriteText(dir / "slow.yaml", config);
  const fs::path csv = dir / "k.csv";
  Child run(HybridtestArgv(RunArgs((dir / "slow.yaml").string(), csv)), dir / "run.log");
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (ReadLines(csv).size() < 4 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_GE(ReadLines(csv).size(), 4u) << run.output();
  ASSERT_TRUE(fs::remove(io::RunLockPath(csv.string())));
  const std::string before = test_support::ReadText(csv);
  const auto [status, out] = Resume(csv, {"--quiet"}, dir / "resume.log");
  EXPECT_EQ(status, 2) << out;
  EXPECT_THAT(out, HasSubstr("a live hybridtest process"));
  // The live run goes on appending; what it had written is intact, and no NUL byte appeared.
  const std::string after = test_support::ReadText(csv);
  EXPECT_EQ(after.substr(0, before.size()), before);
  EXPECT_EQ(after.find('\0'), std::string::npos);
  run.Signal(SIGINT);
  EXPECT_EQ(run.WaitExit(60.0), 130) << run.output();
  EXPECT_THAT(Sidecar(csv).value("status", ""), HasSubstr("stopped"));
}

TEST(JournalIsTruth, AKilledWallClockRunGivesTheRightReason) {
  const fs::path dir = ResumeTestDir("journal_rt_kill");
  // The real-time storey paced on the wall clock (10 s), the miss policy off so that a loaded
  // machine does not hold it before it is killed.
  std::string config = test_support::ReadText(kSource + "/examples/real-time/storey-ats.yaml");
  const std::string policy = "hold_after_misses: 10";
  config.replace(config.find(policy), policy.size(), "hold_after_misses: 0");
  const std::string model = "file: storey.model.yaml";
  config.replace(config.find(model), model.size(),
                 "file: " + kSource + "/examples/real-time/storey.model.yaml");
  test_support::WriteText(dir / "wall.yaml", config);
  const fs::path csv = dir / "w.csv";
  Child run(HybridtestArgv({"run", (dir / "wall.yaml").string(), "--clock", "wall", "--out",
                            csv.string(), "--quiet"}),
            dir / "run.log");
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (ReadLines(csv).size() < 50 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  run.Signal(SIGKILL);
  const int status = run.WaitExit(30.0);
  if (status != 128 + SIGKILL) GTEST_SKIP() << "the run ended before the kill: " << run.output();
  ASSERT_GE(ReadLines(csv).size(), 2u);
  const RunFilesText before = RunFilesText::Of(csv);
  const auto [code, out] = Resume(csv, {"--quiet"}, dir / "resume.log");
  EXPECT_EQ(code, 2) << out;
  EXPECT_THAT(out, HasSubstr("real-time run: it writes its state only when it stops"));
  EXPECT_THAT(out, HasSubstr("killed (status 'running'"));
  EXPECT_THAT(out, ::testing::Not(HasSubstr("before its first committed row")));
  EXPECT_TRUE(RunFilesText::Of(csv) == before);
}

}  // namespace
}  // namespace hybridtest::testing
