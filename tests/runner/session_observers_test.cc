// Session: the run as the caller holds it — observers see every trial and commit in order,
// a run in memory writes no file, RequestStop() holds the run and GetState()/SetState()
// continue it bit for bit, and a step with observers allocates nothing.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "hybridtest/io/run_reader.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/multibody/kane.h"
#include "hybridtest/runner/session.h"
#include "hybridtest/runner/stop_request.h"
#include "runner/dummy_spec.h"
#include "support/alloc_counter.h"

namespace hybridtest::runner {
namespace {

namespace fs = std::filesystem;

io::RunSpec DummySpec(double duration = 0.02) { return testing::DummySpec(duration); }

// Records everything it is told, in order.
class Recorder final : public SessionObserver {
 public:
  void OnStart(const StartEvent& e) override {
    events.push_back("start");
    start_physical = e.has_physical;
    start_substructures = e.substructures.size();
  }
  void OnTrial(const TrialEvent& e) override {
    events.push_back("trial");
    trial_stages.push_back(e.at.stage);
    ASSERT_EQ(e.exchanges.size(), 1u);
    if (e.at.stage < 0) {  // a resume move: no slot displacements or forces
      EXPECT_TRUE(e.d.empty());
      return;
    }
    ASSERT_EQ(e.d.size(), 3u);
    ASSERT_EQ(e.r.size(), 3u);
    ASSERT_EQ(e.exchanges.size(), 1u);
    // The loopback's command is p0 + d of slot r1 (p0 = 0) and its force 7200 d.
    EXPECT_EQ(e.exchanges[0].command, e.d[0]);
    EXPECT_EQ(e.r[0], e.exchanges[0].force);
  }
  void OnCommit(const CommitEvent& e) override {
    events.push_back("commit");
    rows.push_back(std::vector<double>(e.row.begin(), e.row.end()));
    EXPECT_EQ(e.row[0], e.t);
    // What the files, the monitor and the progress display need, carried by the event.
    evaluations.push_back(e.statistics.physical_evaluations);
    steps_left.push_back(e.steps_left);
    finished.push_back(e.finished);
    if (e.state) state_steps.push_back(e.state().scheme.value("step", -1L));
  }
  void OnStop(const StopEvent& e) override {
    events.push_back(std::string("stop:") + StatusName(e.status));
    stop_step = e.committed_step;
    stop_has_state = e.state.has_value();
  }
  bool start_physical = false;
  std::size_t start_substructures = 0;
  std::vector<long> evaluations, steps_left, state_steps;
  std::vector<bool> finished;
  long stop_step = -2;
  bool stop_has_state = false;
  std::vector<std::string> events;
  std::vector<int> trial_stages;
  std::vector<std::vector<double>> rows;
};

TEST(SessionObservers, SeeEveryTrialAndCommitInOrder) {
  Session session(DummySpec());
  Recorder recorder;
  session.AddObserver(recorder);
  StepResult r = session.Initialize();
  ASSERT_EQ(r.status, SessionStatus::kWorking) << r.reason;
  long steps = 0;
  while (r.status == SessionStatus::kWorking) {
    r = session.Step();
    ++steps;
  }
  ASSERT_EQ(r.status, SessionStatus::kFinished) << r.reason;
  EXPECT_EQ(steps, 20);
  // start, trial + commit of x0, then per Heun step: trial (stage 1), trial (stage 0 of the
  // next step), commit; then the stop.
  ASSERT_EQ(recorder.events.size(), 1u + 2u + 3u * 20u + 1u);
  EXPECT_EQ(recorder.events[0], "start");
  EXPECT_EQ(recorder.events[1], "trial");
  EXPECT_EQ(recorder.events[2], "commit");
  for (int k = 0; k < 20; ++k) {
    EXPECT_EQ(recorder.events[3 + 3 * k], "trial");
    EXPECT_EQ(recorder.events[4 + 3 * k], "trial");
    EXPECT_EQ(recorder.events[5 + 3 * k], "commit");
  }
  EXPECT_EQ(recorder.events.back(), "stop:finished");
  EXPECT_EQ(recorder.rows.size(), 21u);
  EXPECT_EQ(session.statistics().steps, 20);
  EXPECT_EQ(session.statistics().rows, 21);
  EXPECT_EQ(session.statistics().physical_evaluations, 41);
  // The last row is the committed point.
  const auto& p = session.committed();
  for (int i = 0; i < 8; ++i) EXPECT_EQ(recorder.rows.back()[1 + i], p.x(i));
  // The events carried the run: its substructures, the evaluations so far (x0's trial, then
  // two per Heun step), the steps left, the end on the last row only, the state at each row.
  EXPECT_TRUE(recorder.start_physical);
  EXPECT_EQ(recorder.start_substructures, session.substructures().size());
  for (long k = 0; k <= 20; ++k) {
    const auto i = static_cast<std::size_t>(k);
    EXPECT_EQ(recorder.evaluations[i], 1 + 2 * k);
    EXPECT_EQ(recorder.steps_left[i], 20 - k);
    EXPECT_EQ(recorder.finished[i], k == 20);
  }
  ASSERT_EQ(recorder.state_steps.size(), 21u);
  EXPECT_EQ(recorder.state_steps.back(), 20);
  EXPECT_EQ(recorder.stop_step, 20);
  EXPECT_TRUE(recorder.stop_has_state);
  // After the end, Step() keeps answering the same.
  EXPECT_EQ(session.Step().status, SessionStatus::kFinished);
}

TEST(SessionObservers, ARunInMemoryWritesNoFile) {
  const fs::path dir = fs::temp_directory_path() / ("hybridtest_session_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path cwd = fs::current_path();
  fs::current_path(dir);
  io::RunSpec spec = DummySpec();
  spec.output.csv_path = "would-be.csv";  // ignored: files are off
  Session session(std::move(spec));
  const StepResult r = session.Run();
  fs::current_path(cwd);
  EXPECT_EQ(r.status, SessionStatus::kFinished) << r.reason;
  EXPECT_TRUE(fs::is_empty(dir)) << "a run in memory wrote into " << dir;
  fs::remove_all(dir);
}

// Stops after `stop_after` steps on request, then continues from GetState() in a new session.
TEST(SessionObservers, RequestStopHoldsAndSetStateContinuesBitForBit) {
  Recorder full;
  {
    Session session(DummySpec());
    session.AddObserver(full);
    ASSERT_EQ(session.Run().status, SessionStatus::kFinished);
  }
  Recorder first, second;
  RunState saved;
  {
    Session session(DummySpec());
    session.AddObserver(first);
    ASSERT_EQ(session.Initialize().status, SessionStatus::kWorking);
    for (int k = 0; k < 6; ++k) ASSERT_EQ(session.Step().status, SessionStatus::kWorking);
    session.RequestStop();
    const StepResult r = session.Step();
    ASSERT_EQ(r.status, SessionStatus::kHeld);
    EXPECT_NE(r.reason.find("interrupted"), std::string::npos) << r.reason;
    EXPECT_THROW(std::rethrow_exception(session.error()), Interrupted);
    EXPECT_EQ(first.events.back(), "stop:held");
    saved = session.GetState();
    saved.rows = session.statistics().rows;
  }
  EXPECT_EQ(first.rows.size(), 8u);  // rows 0..7
  {
    Session session(DummySpec());
    session.AddObserver(second);
    session.SetState(saved);
    ASSERT_EQ(session.Run().status, SessionStatus::kFinished);
  }
  // Rows 8.. of the continued run equal the uninterrupted run's bit for bit.
  ASSERT_EQ(first.rows.size() + second.rows.size(), full.rows.size());
  for (std::size_t k = 0; k < second.rows.size(); ++k) {
    EXPECT_EQ(second.rows[k], full.rows[first.rows.size() + k]) << "row " << first.rows.size() + k;
  }
  // The resume re-imposed the committed command once (stage −1) before stepping on.
  ASSERT_FALSE(second.trial_stages.empty());
  EXPECT_EQ(second.trial_stages.front(), -1);
}

TEST(SessionObservers, StepsWithObserversDoNotAllocate) {
  if (!test_support::kCanCountAllocations) GTEST_SKIP() << "allocations cannot be counted here";
  class Counting final : public SessionObserver {
   public:
    void OnTrial(const TrialEvent& e) override { sum += e.r[0]; }
    void OnCommit(const CommitEvent& e) override { sum += e.row[0]; }
    double sum = 0.0;
  } counting;
  Session session(DummySpec(0.05));
  session.AddObserver(counting);
  ASSERT_EQ(session.Initialize().status, SessionStatus::kWorking);
  session.Step();  // warm-up
  const long allocations = test_support::CountAllocations([&] {
    for (int k = 0; k < 10; ++k) session.Step();
  });
  EXPECT_EQ(allocations, 0);
  EXPECT_NE(counting.sum, 0.0);
}

TEST(SessionObservers, AFailureIsAStatusNotAnException) {
  io::RunSpec spec = DummySpec();
  // A stroke of ±1 mm: the initial deflection of 2 mm is refused before anything moves.
  spec.substructures[0].physical->limits.stroke_min = -0.001;
  spec.substructures[0].physical->limits.stroke_max = 0.001;
  spec.substructures[0].physical->limits.max_increment = 0.0005;
  Session session(std::move(spec));
  Recorder recorder;
  session.AddObserver(recorder);
  const StepResult r = session.Initialize();
  EXPECT_EQ(r.status, SessionStatus::kStopped);
  EXPECT_NE(r.reason.find("safety stop"), std::string::npos) << r.reason;
  EXPECT_EQ(recorder.events.back(), "stop:stopped");
  EXPECT_EQ(session.Step().status, SessionStatus::kStopped);
}

}  // namespace
}  // namespace hybridtest::runner
