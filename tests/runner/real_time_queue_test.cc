// A real-time run's files behind the lock-free queue (real_time_run.h): the journal, the stage
// record and the state are those of the same run with the files on the stepping thread, byte
// for byte (virtual clock); they are written on another thread; and a queue the files cannot
// keep up with holds the run with every committed row kept, instead of blocking the loop.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/runner/paced_loop.h"
#include "hybridtest/runner/real_time_run.h"
#include "hybridtest/runner/run_state.h"
#include "support/temp_dir.h"

namespace hybridtest::runner {
namespace {

namespace fs = std::filesystem;
const std::string kDir = std::string(HYBRIDTEST_SOURCE_DIR) + "/examples/real-time/";

// storey-ats.yaml for `duration` seconds, its files at `csv`.
io::RunSpec StoreySpec(const fs::path& csv, double duration) {
  std::string text = test_support::ReadText(kDir + "storey-ats.yaml");
  const std::string from = "duration: 10.0";
  text.replace(text.find(from), from.size(), "duration: " + std::to_string(duration));
  io::RunSpec spec = io::CompileRunSpec(
      io::ParseSimulationConfig(YamlInput::FromText(text, kDir + "storey-ats.yaml")));
  spec.output.csv_path = csv.string();
  spec.quiet = true;
  return spec;
}

// Records the steps it sees, the thread it sees them on, and may be slow.
class Recorder final : public SessionObserver {
 public:
  explicit Recorder(std::chrono::microseconds delay = {}) : delay_(delay) {}
  void OnTrial(const TrialEvent&) override { ++trials; }
  void OnCommit(const CommitEvent& e) override {
    if (delay_.count() > 0) std::this_thread::sleep_for(delay_);
    if (e.kind == RowKind::kCommitted) steps.push_back(e.step);
    thread = std::this_thread::get_id();
  }
  std::vector<long> steps;
  long trials = 0;
  std::thread::id thread;

 private:
  std::chrono::microseconds delay_;
};

long CsvRows(const fs::path& csv) {
  const std::string text = test_support::ReadText(csv);
  long lines = 0;
  for (char c : text) lines += c == '\n' ? 1 : 0;
  return lines - 1;  // the header
}

TEST(RealTimeQueue, TheQueuedFilesAreTheFilesOfTheSteppingThread) {
  const fs::path dir = test_support::FreshTempDir("rt_queue_same");
  // The files on the stepping thread: the paced loop without RealTimeRun's routing.
  Session direct(StoreySpec(dir / "direct.csv", 0.5));
  Recorder on_loop;
  direct.AddObserver(on_loop);
  VirtualClock clock;
  PacedLoop loop(direct, clock);
  ASSERT_EQ(loop.Run().status, SessionStatus::kFinished);
  // The files behind the queue.
  Session queued(StoreySpec(dir / "queued.csv", 0.5));
  Recorder behind;
  queued.AddObserver(behind);
  RealTimeRun run(queued, "virtual", true);
  const StepResult r = run.Run();
  ASSERT_EQ(r.status, SessionStatus::kFinished) << r.reason;
  ASSERT_NE(run.queue(), nullptr);

  const std::string a = test_support::ReadText(dir / "direct.csv");
  EXPECT_GT(a.size(), 1000u);
  EXPECT_EQ(a, test_support::ReadText(dir / "queued.csv"));
  EXPECT_EQ(CsvRows(dir / "queued.csv"), 513);  // rows 0..512
  EXPECT_EQ(test_support::ReadText(dir / "direct.stages.csv"),
            test_support::ReadText(dir / "queued.stages.csv"));
  // The state, saved at the stop, belongs to the last row in both.
  const RunState sa = LoadRunState((dir / "direct.state.json").string());
  const RunState sb = LoadRunState((dir / "queued.state.json").string());
  EXPECT_EQ(sa.rows, 513);
  EXPECT_EQ(sb.rows, 513);
  EXPECT_EQ(sa.row, sb.row);
  EXPECT_EQ(sa.scheme, sb.scheme);
  // Every event reached the observers behind the queue, on another thread.
  EXPECT_EQ(behind.steps, on_loop.steps);
  EXPECT_EQ(behind.trials, on_loop.trials);
  EXPECT_EQ(on_loop.thread, std::this_thread::get_id());
  EXPECT_NE(behind.thread, std::this_thread::get_id());
  EXPECT_FALSE(run.loop()->statistics().held_on_queue);
  EXPECT_GT(run.loop()->statistics().queue_min_free, kQueueReserve);
}

// The wall clock's policy without sleeping: time jumps to each deadline, as on a machine that
// is always on time, but the loop treats it as the wall clock (it may not wait for the files).
class PunctualWallClock final : public Clock {
 public:
  double Now() const override { return now_; }
  void WaitUntil(double t) override { now_ = std::max(now_, t); }
  bool is_virtual() const override { return false; }
  std::string name() const override { return "punctual"; }

 private:
  double now_ = 0.0;
};

TEST(RealTimeQueue, OnTheWallClockAQueueTheFilesCannotKeepUpWithHoldsTheRunKeepingEveryRow) {
  const fs::path dir = test_support::FreshTempDir("rt_queue_full");
  io::RunSpec spec = StoreySpec(dir / "slow.csv", 0.5);
  spec.real_time.queue = 64;
  Session session(std::move(spec));
  Recorder slow(std::chrono::microseconds(2000));  // far slower than the loop
  session.AddObserver(slow);
  PunctualWallClock clock;
  PacedLoop loop(session, clock);
  const std::unique_ptr<LockFreeObserver> queue = QueueObservers(session, loop);
  ASSERT_NE(queue, nullptr);
  const StepResult r = loop.Run();
  // A hold (resumable, every actuator holding), not a failure of a full queue.
  EXPECT_EQ(r.status, SessionStatus::kHeld) << r.reason;
  EXPECT_NE(r.reason.find("queue"), std::string::npos) << r.reason;
  const PacedStatistics& stats = loop.statistics();
  EXPECT_TRUE(stats.held_on_queue);
  EXPECT_EQ(stats.queue_waits, 0);
  EXPECT_LT(stats.ticks, 512);
  // Every committed row reached the journal and the slow observer, in order.
  const long rows = session.statistics().rows;
  EXPECT_EQ(CsvRows(dir / "slow.csv"), rows);
  ASSERT_EQ(static_cast<long>(slow.steps.size()), rows);
  for (long k = 0; k < rows; ++k) EXPECT_EQ(slow.steps[static_cast<std::size_t>(k)], k);
  // The state belongs to the last row: the run can be resumed.
  const RunState state = LoadRunState((dir / "slow.state.json").string());
  EXPECT_EQ(state.rows, rows);
  EXPECT_NO_THROW(VerifyRunStateAgainstJournal(state, (dir / "slow.csv").string()));
}

TEST(RealTimeQueue, InVirtualTimeTheLoopWaitsForASlowQueueAndTheRunIsTheSame) {
  const fs::path dir = test_support::FreshTempDir("rt_queue_wait");
  io::RunSpec spec = StoreySpec(dir / "slow.csv", 0.25);
  spec.real_time.queue = 64;
  Session session(std::move(spec));
  Recorder slow(std::chrono::microseconds(300));
  session.AddObserver(slow);
  RealTimeRun run(session, "virtual", true);
  const StepResult r = run.Run();
  ASSERT_EQ(r.status, SessionStatus::kFinished) << r.reason;
  EXPECT_GT(run.loop()->statistics().queue_waits, 0);
  EXPECT_FALSE(run.loop()->statistics().held_on_queue);
  // The same journal as a run whose files never waited.
  Session fast(StoreySpec(dir / "fast.csv", 0.25));
  RealTimeRun fast_run(fast, "virtual", true);
  ASSERT_EQ(fast_run.Run().status, SessionStatus::kFinished);
  EXPECT_EQ(test_support::ReadText(dir / "slow.csv"), test_support::ReadText(dir / "fast.csv"));
  EXPECT_EQ(static_cast<long>(slow.steps.size()), 257);
}

}  // namespace
}  // namespace hybridtest::runner
