// Session, the loop policy: with fake substructures that record (step, stage, t, d), check
// the order of trials and commits, what the journal row n holds, and what a failure at stage 0
// or stage 1 of a step leaves behind (rows, NaN forces, holds, the sidecar's stop report).
#include "hybridtest/runner/session.h"

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "hybridtest/io/run_reader.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/runner/open_run.h"
#include "runner/fake_substructure.h"

namespace hybridtest::runner {
namespace {

namespace fs = std::filesystem;
using testing::Call;
using testing::CallKind;
using testing::FakeSubstructure;
using testing::Failure;

constexpr long kSteps = 10;
constexpr double kH = 0.001;
constexpr double kStiffness = 7200.0;  // k_b [N/m]

io::SimulationConfig MakeConfig() {
  return io::ParseSimulationConfig(YamlInput::FromText(R"(
model: {name: rotor, blades: 3}
initial_state: {q: [0.01, -0.005, 0.002, 0.0], u: [0.1, 0.0, -0.2, 0.5]}
integrator: {tableau: heun, dt: 0.001}
duration: 0.01
)", "runner_test.yaml"));
}

// The rotor with three fakes (slot 0 physical) and an optional failure of `failing_slot`.
io::RunSpec FakeSpec(const io::SimulationConfig& cfg, std::shared_ptr<std::vector<Call>> log,
                     std::optional<Failure> failure = std::nullopt, int failing_slot = 0) {
  io::RunSpec spec = io::CompileRunSpec(cfg);
  for (int s = 0; s < 3; ++s) {
    auto& sub = spec.substructures[static_cast<std::size_t>(s)];
    const std::optional<Failure> f = s == failing_slot ? failure : std::nullopt;
    sub.law.reset();
    sub.custom = [s, log, f] {
      return std::make_unique<FakeSubstructure>(s, log, kStiffness, s == 0, f);
    };
    sub.custom_is_physical = s == 0;
  }
  spec.quiet = true;
  return spec;
}

struct Outcome {
  std::vector<Call> calls;
  io::RunData run;
  std::optional<io::RunData> stages;
  std::string error;  // what() of the failure, empty if the run completed
  bool safety = false;
  bool transfer = false;
};

// Runs the rotor with three fakes (slot 0 physical) and an optional failure of `failing_slot`.
Outcome RunWithFakes(const std::string& name, std::optional<Failure> failure = std::nullopt,
                     int failing_slot = 0) {
  const fs::path dir = fs::temp_directory_path() /
                       ("hybridtest_runner_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const io::SimulationConfig cfg = MakeConfig();
  EXPECT_EQ(cfg.steps, kSteps);
  auto log = std::make_shared<std::vector<Call>>();
  io::RunSpec spec = FakeSpec(cfg, log, failure, failing_slot);
  spec.output.csv_path = (dir / "run.csv").string();
  Outcome out;
  OpenedRun opened = OpenRun(spec);
  Session session(spec, std::move(opened));
  const StepResult result = session.Run();
  if (result.status != SessionStatus::kFinished) {
    try {
      std::rethrow_exception(session.error());
    } catch (const transfer::SafetyStop& e) {
      out.error = e.what();
      out.safety = true;
    } catch (const TransferError& e) {
      out.error = e.what();
      out.transfer = true;
    }
    EXPECT_EQ(result.status, SessionStatus::kStopped);
    EXPECT_EQ(result.reason, out.error);
  }
  out.calls = *log;
  out.run = io::LoadRun(spec.output.csv_path);
  if (fs::exists(dir / "run.stages.csv")) out.stages = io::LoadRun((dir / "run.stages.csv").string());
  return out;
}

// The trial of `slot` at (step, stage), or fails the test.
const Call& FindTrial(const std::vector<Call>& calls, int slot, long step, int stage) {
  for (const auto& c : calls) {
    if (c.kind == CallKind::kTrial && c.slot == slot && c.step == step && c.stage == stage) return c;
  }
  ADD_FAILURE() << "no trial of slot " << slot << " at step " << step << " stage " << stage;
  static const Call none{CallKind::kTrial};
  return none;
}

std::string Name(CallKind k) {
  switch (k) {
    case CallKind::kActivate: return "activate";
    case CallKind::kTrial: return "trial";
    case CallKind::kCommit: return "commit";
    case CallKind::kHold: return "hold";
    case CallKind::kDeactivate: return "deactivate";
  }
  return "?";
}

TEST(Session, EveryStageOfEveryStepIsTriedInOrderAndCommitFollowsStageZero) {
  const Outcome out = RunWithFakes("order");
  ASSERT_TRUE(out.error.empty()) << out.error;
  // The expected call sequence, slot by slot.
  std::vector<Call> expected;
  for (int s = 0; s < 3; ++s) expected.push_back({CallKind::kActivate, s});
  auto trials = [&](long step, int stage, double t) {
    for (int s = 0; s < 3; ++s) expected.push_back({CallKind::kTrial, s, step, stage, t});
  };
  auto commits = [&] {
    for (int s = 0; s < 3; ++s) expected.push_back({CallKind::kCommit, s});
  };
  for (long n = 0; n < kSteps; ++n) {
    trials(n, 0, static_cast<double>(n) * kH);
    commits();
    trials(n, 1, static_cast<double>(n + 1) * kH);  // Heun: c = [0, 1]
  }
  trials(kSteps, 0, kSteps * kH);  // the last committed state gets its row
  commits();
  for (int s = 0; s < 3; ++s) expected.push_back({CallKind::kDeactivate, s});

  ASSERT_EQ(out.calls.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const Call& got = out.calls[i];
    const Call& want = expected[i];
    SCOPED_TRACE("call " + std::to_string(i));
    ASSERT_EQ(Name(got.kind), Name(want.kind));
    EXPECT_EQ(got.slot, want.slot);
    if (got.kind == CallKind::kTrial) {
      EXPECT_EQ(got.step, want.step);
      EXPECT_EQ(got.stage, want.stage);
      EXPECT_NEAR(got.t, want.t, 1e-15);
    }
  }
}

TEST(Session, JournalRowNHoldsXnAndTheForcesMeasuredAtStageZero) {
  const Outcome out = RunWithFakes("rows");
  ASSERT_TRUE(out.error.empty()) << out.error;
  const io::RunData& run = out.run;
  ASSERT_EQ(run.num_rows(), kSteps + 1);
  EXPECT_EQ(run.metadata.at("status"), "completed");
  EXPECT_EQ(run.metadata.at("statistics").at("steps"), kSteps);
  EXPECT_EQ(run.metadata.at("statistics").at("physical_evaluations"), 2 * kSteps + 1);
  const Eigen::VectorXd t = run.Get("t");
  for (long n = 0; n <= kSteps; ++n) {
    SCOPED_TRACE("row " + std::to_string(n));
    EXPECT_NEAR(t(n), static_cast<double>(n) * kH, 1e-15);
    for (int s = 0; s < 3; ++s) {
      const std::string q = fmt::format("q{}", s + 1), r = fmt::format("r{}", s + 1);
      const Call& stage0 = FindTrial(out.calls, s, n, 0);
      // The slot displacement of r_s is q_s: the trial at stage 0 saw exactly x_n.
      EXPECT_EQ(run.Get(q)(n), stage0.d);
      // The row holds the force of that very trial (17 digits round-trip exactly) ...
      EXPECT_EQ(run.Get(r)(n), stage0.r);
      // ... and not the one of stage 1 (tagged with +0.25 N).
      if (n < kSteps) {
        EXPECT_NE(run.Get(r)(n), FindTrial(out.calls, s, n, 1).r);
      }
    }
    EXPECT_EQ(run.Get("r1_command")(n), FakeSubstructure::kP0 + FindTrial(out.calls, 0, n, 0).d);
    EXPECT_EQ(run.Get("r1_force")(n), FindTrial(out.calls, 0, n, 0).r);
  }
  // The initial state is row 0.
  EXPECT_EQ(run.Get("q1")(0), 0.01);
  EXPECT_EQ(run.Get("u4")(0), 0.5);
  EXPECT_FALSE(run.Has("r2_command")) << "numerical slots have no physical channels";

  // The stage record holds every physical exchange, in order.
  ASSERT_TRUE(out.stages.has_value());
  ASSERT_EQ(out.stages->num_rows(), 2 * kSteps + 1);
  for (long i = 0; i < out.stages->num_rows(); ++i) {
    EXPECT_EQ(out.stages->Get("step")(i), static_cast<double>(i / 2));
    EXPECT_EQ(out.stages->Get("stage")(i), static_cast<double>(i % 2));
    const Call& c = FindTrial(out.calls, 0, i / 2, static_cast<int>(i % 2));
    EXPECT_EQ(out.stages->Get("r1_force")(i), c.r);
  }
}

// Rows 0..k-1 of a failed run equal those of the completed run, bit for bit.
void ExpectSamePrefix(const io::RunData& failed, const io::RunData& full, long rows) {
  for (long n = 0; n < rows; ++n) {
    for (int c = 0; c < full.num_channels(); ++c) {
      ASSERT_EQ(failed.values(n, c), full.values(n, c))
          << "row " << n << " channel " << full.channels[c].name;
    }
  }
}

void ExpectHeldAndNotDeactivated(const std::vector<Call>& calls) {
  for (int s = 0; s < 3; ++s) {
    bool held = false, deactivated = false;
    for (const auto& c : calls) {
      held = held || (c.kind == CallKind::kHold && c.slot == s);
      deactivated = deactivated || (c.kind == CallKind::kDeactivate && c.slot == s);
    }
    EXPECT_TRUE(held) << "slot " << s << " was not held";
    EXPECT_FALSE(deactivated) << "slot " << s << " was deactivated after a failure";
  }
}

TEST(Session, FailureAtStageOneOfStepKLeavesRowsZeroToK) {
  constexpr long k = 4;
  const Outcome full = RunWithFakes("full1");
  const Outcome out = RunWithFakes("stage1", Failure{k, 1, false}, 1);
  ASSERT_TRUE(out.transfer) << "expected the TransferError to propagate";
  EXPECT_NE(out.error.find("connection lost"), std::string::npos);
  ASSERT_EQ(out.run.num_rows(), k + 1);
  ExpectSamePrefix(out.run, full.run, k + 1);  // row k was written at stage 0
  EXPECT_TRUE(std::isfinite(out.run.Get("r2")(k)));
  ExpectHeldAndNotDeactivated(out.calls);
  // Nothing is tried after the failure.
  long trials_after = 0;
  bool failed = false;
  for (const auto& c : out.calls) {
    if (failed && c.kind == CallKind::kTrial) ++trials_after;
    failed = failed || (c.kind == CallKind::kTrial && std::isnan(c.r));
  }
  EXPECT_EQ(trials_after, 0);

  const nlohmann::json& meta = out.run.metadata;
  EXPECT_EQ(meta.at("status").get<std::string>().rfind("stopped: ", 0), 0u) << meta.at("status");
  EXPECT_NE(meta.at("status").get<std::string>().find("connection lost"), std::string::npos);
  EXPECT_EQ(meta.at("statistics").at("steps"), k);
  EXPECT_EQ(meta.at("statistics").at("rows"), k + 1);
  EXPECT_EQ(meta.at("statistics").at("stop").at("kind"), "transfer");
}

TEST(Session, FailureAtStageZeroOfStepKLeavesRowKWithNanForces) {
  constexpr long k = 4;
  const Outcome full = RunWithFakes("full0");
  const Outcome out = RunWithFakes("stage0", Failure{k, 0, true}, 0);
  ASSERT_TRUE(out.safety) << "expected the SafetyStop to propagate";
  ASSERT_EQ(out.run.num_rows(), k + 1);
  ExpectSamePrefix(out.run, full.run, k);
  // Row k: the committed state x_k, with no measured forces.
  const io::RunData& run = out.run;
  for (const char* name : {"t", "q1", "q2", "q3", "q4", "u1", "u2", "u3", "u4"}) {
    EXPECT_EQ(run.Get(name)(k), full.run.Get(name)(k)) << name;
  }
  for (const char* name : {"r1", "r2", "r3", "r1_command", "r1_position", "r1_force",
                           "r1_lab_time"}) {
    EXPECT_TRUE(std::isnan(run.Get(name)(k))) << name << " = " << run.Get(name)(k);
  }
  ExpectHeldAndNotDeactivated(out.calls);
  // No commit of step k: its stage-0 trial failed.
  long commits = 0;
  for (const auto& c : out.calls) commits += c.kind == CallKind::kCommit && c.slot == 0;
  EXPECT_EQ(commits, k);

  const nlohmann::json& stop = run.metadata.at("statistics").at("stop");
  EXPECT_EQ(run.metadata.at("status").get<std::string>().rfind("stopped: safety stop: stroke_max", 0),
            0u) << run.metadata.at("status");
  EXPECT_EQ(stop.at("kind"), "safety");
  EXPECT_EQ(stop.at("limit"), "stroke_max");
  EXPECT_EQ(stop.at("step"), k);
  EXPECT_EQ(stop.at("stage"), 0);
  EXPECT_DOUBLE_EQ(stop.at("value").get<double>(), FakeSubstructure::kP0 + run.Get("q1")(k));
  ASSERT_EQ(stop.at("history").size(), 1u);
  EXPECT_EQ(stop.at("history")[0].at("answered"), false);
  EXPECT_EQ(run.metadata.at("statistics").at("steps"), k);
  // The stage record ends with the last exchange that succeeded.
  ASSERT_TRUE(out.stages.has_value());
  EXPECT_EQ(out.stages->num_rows(), 2 * k);
  EXPECT_EQ(out.stages->metadata.at("status"), run.metadata.at("status"));
}

TEST(Session, FailureAtTheLastStateLeavesEveryStepAndANanLastRow) {
  const Outcome full = RunWithFakes("fullN");
  const Outcome out = RunWithFakes("last", Failure{kSteps, 0, false}, 2);
  ASSERT_TRUE(out.transfer);
  ASSERT_EQ(out.run.num_rows(), kSteps + 1);
  ExpectSamePrefix(out.run, full.run, kSteps);
  EXPECT_EQ(out.run.Get("q3")(kSteps), full.run.Get("q3")(kSteps));
  EXPECT_TRUE(std::isnan(out.run.Get("r3")(kSteps)));
  EXPECT_EQ(out.run.metadata.at("statistics").at("steps"), kSteps);
}

TEST(Session, RejectsAWrongNumberOfSubstructures) {
  io::RunSpec spec = io::CompileRunSpec(MakeConfig());
  spec.substructures.pop_back();
  EXPECT_THROW(Session{spec}, ConfigError);
}

}  // namespace
}  // namespace hybridtest::runner
