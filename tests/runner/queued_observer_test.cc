// QueuedObserver: a slow observer behind a bounded queue sees every trial and commit in the
// session's order, a full queue makes the stepping thread wait (nothing dropped), the durable
// mode has every commit delivered before the next trial, and the inner observer's exception
// stops the run.
#include "hybridtest/runner/queued_observer.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "runner/dummy_spec.h"

namespace hybridtest::runner {
namespace {

io::RunSpec DummySpec() { return testing::DummySpec(0.03); }

// Keeps a flat log of what it saw; optionally slow, optionally failing at commit k.
class Log final : public SessionObserver {
 public:
  explicit Log(int delay_us = 0, int fail_at_commit = -1)
      : delay_us_(delay_us), fail_at_commit_(fail_at_commit) {}
  void OnTrial(const TrialEvent& e) override {
    Pause();
    values.push_back(100.0 + e.at.stage);
    values.insert(values.end(), e.d.begin(), e.d.end());
    values.insert(values.end(), e.r.begin(), e.r.end());
    for (const auto& x : e.exchanges) values.push_back(x.force);
    ++trials;
  }
  void OnCommit(const CommitEvent& e) override {
    Pause();
    if (commits == fail_at_commit_) throw IoError("the observer's disk is full");
    values.push_back(200.0);
    values.insert(values.end(), e.row.begin(), e.row.end());
    ++commits;
  }
  void OnStop(const StopEvent& e) override { stopped = StatusName(e.status); }
  std::vector<double> values;
  int trials = 0, commits = 0;
  std::string stopped;

 private:
  void Pause() const {
    if (delay_us_ > 0) std::this_thread::sleep_for(std::chrono::microseconds(delay_us_));
  }
  int delay_us_, fail_at_commit_;
};

TEST(QueuedObserver, DeliversEveryEventInOrderAndWaitsWhenFull) {
  Log direct;
  {
    Session session(DummySpec());
    session.AddObserver(direct);
    ASSERT_EQ(session.Run().status, SessionStatus::kFinished);
  }
  Log slow(200);
  QueuedObserver queued(slow, 4);
  {
    Session session(DummySpec());
    session.AddObserver(queued);
    ASSERT_EQ(session.Run().status, SessionStatus::kFinished);
  }
  EXPECT_EQ(slow.stopped, "finished");
  EXPECT_EQ(slow.commits, 31);
  EXPECT_EQ(slow.values, direct.values);
  // 92 events into 4 slots at 200 µs each: the stepping thread (a few µs per event) waited.
  EXPECT_GT(queued.waits(), 0);
}

TEST(QueuedObserver, DurableModeDeliversEveryCommitBeforeTheNextTrial) {
  // Checked from the session's side: before every trial, the inner observer has seen every
  // commit the session published.
  class Check final : public SessionObserver {
   public:
    explicit Check(const Log& inner) : inner_(inner) {}
    void OnCommit(const CommitEvent&) override { ++published; }
    void BeforeTrial(const schemes::TrialPoint&) override {
      // The queue's own BeforeTrial ran first (it was added first) and drained.
      if (inner_.commits != published) ++behind;
    }
    int published = 0, behind = 0;

   private:
    const Log& inner_;
  };
  Log slow(300);
  QueuedObserver queued(slow, 8, /*durable_before_moves=*/true);
  Check check(slow);
  Session session(DummySpec());
  session.AddObserver(queued);
  session.AddObserver(check);
  ASSERT_EQ(session.Run().status, SessionStatus::kFinished);
  EXPECT_EQ(check.published, 31);
  EXPECT_EQ(check.behind, 0);
}

TEST(QueuedObserver, TheInnerObserversFailureStopsTheRun) {
  Log failing(0, 5);
  QueuedObserver queued(failing, 2);
  Session session(DummySpec());
  session.AddObserver(queued);
  const StepResult r = session.Run();
  EXPECT_EQ(r.status, SessionStatus::kStopped);
  EXPECT_NE(r.reason.find("disk is full"), std::string::npos) << r.reason;
  EXPECT_EQ(failing.stopped, "stopped");
  EXPECT_LT(session.statistics().steps, 30);
}

}  // namespace
}  // namespace hybridtest::runner
