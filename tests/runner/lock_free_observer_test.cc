// LockFreeObserver: every row reaches the inner observer in order on another thread, and a
// full ring stops the producer with an error instead of making it wait.
#include "hybridtest/runner/lock_free_observer.h"

#include <gtest/gtest.h>

#include <atomic>
#include <string>
#include <thread>
#include <vector>

#include "hybridtest/common/error.h"
#include "runner/dummy_spec.h"

namespace hybridtest::runner {
namespace {

class Recorder final : public SessionObserver {
 public:
  void OnCommit(const CommitEvent& e) override {
    while (blocked.load()) std::this_thread::yield();
    steps.push_back(e.step);
    sums.push_back(e.row[0] + e.row[1]);
    evaluations.push_back(e.statistics.physical_evaluations);
    steps_left.push_back(e.steps_left);
    if (e.finished) ++finished;
    if (e.state) ++with_state;
    consumer = std::this_thread::get_id();
  }
  void OnStop(const StopEvent&) override { stopped = true; }
  std::atomic<bool> blocked{false};
  std::vector<long> steps;
  std::vector<double> sums;
  std::vector<long> evaluations, steps_left;
  int finished = 0, with_state = 0;
  std::thread::id consumer;
  bool stopped = false;
};

StartEvent StartOf(const Session& session) {
  return {session.spec(), session.slot_map(), session.substructures(), false, nullptr, ""};
}

StopEvent Stopped(SessionStatus status, std::string reason) {
  StopEvent e;
  e.status = status;
  e.reason = std::move(reason);
  e.statistics = nlohmann::json::object();
  return e;
}

void Commit(LockFreeObserver& o, long step) {
  const std::vector<double> x{1.0, 2.0}, r{3.0}, row{static_cast<double>(step), 0.5};
  CommitEvent e;
  e.step = step;
  e.t = 0.001 * static_cast<double>(step);
  e.x = x;
  e.r = r;
  e.row = row;
  e.statistics.physical_evaluations = 3 * step;
  e.finished = step == 9999;
  e.steps_left = 9999 - step;
  e.state = [] { return RunState{}; };  // the stepping thread's only
  o.OnCommit(e);
}

TEST(LockFreeObserver, DeliversEveryRowInOrderOnAnotherThread) {
  Session session(testing::DummySpec(0.01));
  Recorder inner;
  LockFreeObserver queued(inner, 20000, 8);
  queued.OnStart(StartOf(session));
  for (long k = 0; k < 10000; ++k) Commit(queued, k);
  queued.OnStop(Stopped(SessionStatus::kFinished, ""));
  ASSERT_EQ(inner.steps.size(), 10000u);
  for (long k = 0; k < 10000; ++k) {
    ASSERT_EQ(inner.steps[static_cast<std::size_t>(k)], k);
    ASSERT_EQ(inner.sums[static_cast<std::size_t>(k)], static_cast<double>(k) + 0.5);
    // What the event carries for the files, the monitor and the progress display.
    ASSERT_EQ(inner.evaluations[static_cast<std::size_t>(k)], 3 * k);
    ASSERT_EQ(inner.steps_left[static_cast<std::size_t>(k)], 9999 - k);
  }
  EXPECT_EQ(inner.finished, 1);
  EXPECT_EQ(inner.with_state, 0);  // the state is never called from the queue's thread
  EXPECT_NE(inner.consumer, std::this_thread::get_id());
  EXPECT_TRUE(inner.stopped);
}

TEST(LockFreeObserver, AFullRingThrowsInsteadOfWaiting) {
  Session session(testing::DummySpec(0.01));
  Recorder inner;
  inner.blocked = true;  // the consumer is stuck in the first row
  LockFreeObserver queued(inner, 4, 8);
  queued.OnStart(StartOf(session));
  for (long k = 0; k < 4; ++k) Commit(queued, k);
  EXPECT_THROW(Commit(queued, 4), Error);
  inner.blocked = false;
  queued.OnStop(Stopped(SessionStatus::kStopped, "full"));
  EXPECT_EQ(inner.steps.size(), 4u);
}

// Trials and commits of two inner observers, interleaved, in the session's order.
class Sequence final : public SessionObserver {
 public:
  void OnTrial(const TrialEvent& e) override {
    log.push_back(1000 * e.at.step + 10 * e.at.stage + static_cast<long>(e.exchanges[1].force));
  }
  void OnCommit(const CommitEvent& e) override { log.push_back(-e.step); }
  std::vector<long> log;
};

TEST(LockFreeObserver, ForwardsTrialsAndCommitsToEveryInnerObserverInOrder) {
  Session session(testing::DummySpec(0.01));
  Sequence a, b;
  LockFreeObserver queued({&a, &b}, 64, 8, 2);
  queued.OnStart(StartOf(session));
  std::vector<long> expected;
  for (long k = 1; k <= 20; ++k) {
    const std::vector<double> d{0.1}, r{2.0};
    std::vector<substructures::Exchange> ex(2);
    ex[1].force = 7.0;
    queued.OnTrial({{k, 1, 0.01 * static_cast<double>(k)}, d, r, ex});
    expected.push_back(1000 * k + 10 + 7);
    Commit(queued, k);
    expected.push_back(-k);
  }
  // More exchanges than it was made for is a programming error, not a silent cut.
  const std::vector<substructures::Exchange> three(3);
  EXPECT_THROW(queued.OnTrial({{21, 0, 0.21}, {}, {}, three}), Error);
  queued.OnStop(Stopped(SessionStatus::kFinished, ""));
  EXPECT_EQ(a.log, expected);
  EXPECT_EQ(b.log, expected);
}

}  // namespace
}  // namespace hybridtest::runner
