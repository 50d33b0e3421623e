// A real-time run's files behind the lock-free queue (real_time_setup.h): the journal and the
// state hold the rows an observer on the stepping thread saw, bit for bit (virtual clock); they
// are written on another thread; and a queue the files cannot keep up with holds the run with
// every committed row kept, instead of blocking the loop.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <sstream>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/runner/open_run.h"
#include "hybridtest/runner/paced_loop.h"
#include "hybridtest/runner/real_time_setup.h"
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
  spec.real_time.clock = "virtual";
  return spec;
}

// Keeps every committed row, on the stepping thread (real_time_safe: never queued).
class RowsOnLoop final : public SessionObserver {
 public:
  void OnCommit(const CommitEvent& e) override {
    rows.emplace_back(e.row.begin(), e.row.end());
    thread = std::this_thread::get_id();
  }
  bool real_time_safe() const override { return true; }
  std::vector<std::vector<double>> rows;
  std::thread::id thread;
};

// The journal's rows (the header skipped; shortest round-trip numbers, so exact).
std::vector<std::vector<double>> JournalRows(const fs::path& csv) {
  std::istringstream in(test_support::ReadText(csv));
  std::string line;
  std::getline(in, line);
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::istringstream cells(line);
    std::string cell;
    while (std::getline(cells, cell, ',')) row.push_back(std::strtod(cell.c_str(), nullptr));
    rows.push_back(std::move(row));
  }
  return rows;
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

TEST(RealTimeQueue, TheQueuedFilesHoldTheRowsOfTheSteppingThread) {
  const fs::path dir = test_support::FreshTempDir("rt_queue_same");
  // The session builds its pacer and puts the files (and `behind`) behind its queue.
  io::RunSpec spec = StoreySpec(dir / "queued.csv", 0.5);
  OpenedRun opened = OpenRun(spec);
  Session session(std::move(spec), std::move(opened));
  RowsOnLoop on_loop;
  Recorder behind;
  session.AddObserver(on_loop);
  session.AddObserver(behind);
  const StepResult r = session.Run();
  ASSERT_EQ(r.status, SessionStatus::kFinished) << r.reason;
  ASSERT_NE(session.paced_loop(), nullptr);

  ASSERT_EQ(on_loop.rows.size(), 513u);  // rows 0..512
  EXPECT_EQ(JournalRows(dir / "queued.csv"), on_loop.rows);
  // The state, saved at the stop, belongs to the last row.
  const RunState state = LoadRunState((dir / "queued.state.json").string());
  EXPECT_EQ(state.rows, 513);
  EXPECT_NO_THROW(VerifyRunStateAgainstJournal(state, (dir / "queued.csv").string()));
  // Every event reached the observers behind the queue, on another thread.
  EXPECT_EQ(static_cast<long>(behind.steps.size()), 513);
  EXPECT_GT(behind.trials, 512);
  EXPECT_EQ(on_loop.thread, std::this_thread::get_id());
  EXPECT_NE(behind.thread, std::this_thread::get_id());
  EXPECT_FALSE(session.paced_loop()->statistics().held_on_queue);
  EXPECT_GT(session.paced_loop()->statistics().queue_min_free, kQueueReserve);
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
  spec.real_time.lock_memory = false;
  PunctualWallClock clock;
  SessionOptions options;
  options.clock = &clock;
  OpenedRun opened = OpenRun(spec);
  Session session(std::move(spec), std::move(opened), std::move(options));
  Recorder slow(std::chrono::microseconds(2000));  // far slower than the loop
  session.AddObserver(slow);
  const StepResult r = session.Run();
  const PacedLoop& loop = *session.paced_loop();
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
  OpenedRun opened = OpenRun(spec);
  Session session(std::move(spec), std::move(opened));
  Recorder slow(std::chrono::microseconds(300));
  session.AddObserver(slow);
  const StepResult r = session.Run();
  ASSERT_EQ(r.status, SessionStatus::kFinished) << r.reason;
  EXPECT_GT(session.paced_loop()->statistics().queue_waits, 0);
  EXPECT_FALSE(session.paced_loop()->statistics().held_on_queue);
  // The same journal as a run whose files never waited.
  io::RunSpec fast_spec = StoreySpec(dir / "fast.csv", 0.25);
  OpenedRun fast_opened = OpenRun(fast_spec);
  Session fast(std::move(fast_spec), std::move(fast_opened));
  ASSERT_EQ(fast.Run().status, SessionStatus::kFinished);
  EXPECT_EQ(test_support::ReadText(dir / "slow.csv"), test_support::ReadText(dir / "fast.csv"));
  EXPECT_EQ(static_cast<long>(slow.steps.size()), 257);
}

}  // namespace
}  // namespace hybridtest::runner
