// examples/06_blade_two_actuators/large-displacement.yaml as a whole run: on the ideal
// two-actuator emulated bench it equals, within 1e-9 (SI), a test-local numerical substructure
// r = J(d)ᵀ K (ℓ(d) − L0) written from the rods' points; it differs visibly from the linear
// setup of its linearisation (large-displacement-linear.yaml); a slot limit stops the run
// naming the slot; and a bad `setup:` or `safety.slots:` is a ConfigError naming its key.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "hybridtest/common/error.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/runner/plan.h"
#include "hybridtest/runner/session.h"
#include "hybridtest/substructures/substructure.h"
#include "support/temp_dir.h"

namespace hybridtest::substructures {
namespace {

namespace fs = std::filesystem;

const std::string kExample =
    std::string(HYBRIDTEST_SOURCE_DIR) + "/examples/06_blade_two_actuators/";

// The specimen of bench-2act.yaml seen through the example's rods, computed from the points:
// flap along x, edge along y; rod k from base b_k to the tip at (d_flap, d_edge).
class RodTwin final : public Substructure {
 public:
  int num_slots() const override { return 2; }
  void Trial(std::span<const double> d, std::span<double> r, const TrialContext&) override {
    const double bx[2] = {-0.25, -0.15}, by[2] = {0.0, -0.20};
    double len[2], nx[2], ny[2], dl[2];
    for (int k = 0; k < 2; ++k) {
      const double x = d[0] - bx[k], y = d[1] - by[k];
      len[k] = std::sqrt(x * x + y * y);
      nx[k] = x / len[k];
      ny[k] = y / len[k];
      dl[k] = len[k] - std::sqrt(bx[k] * bx[k] + by[k] * by[k]);
    }
    const double f0 = 5000.0 * dl[0] + 1200.0 * dl[1];
    const double f1 = 1200.0 * dl[0] + 3000.0 * dl[1];
    r[0] = nx[0] * f0 + nx[1] * f1;
    r[1] = ny[0] * f0 + ny[1] * f1;
  }
  void Commit() override {}
  std::string Describe() const override { return "test twin: rods, r = J(d)ᵀ K (ℓ(d) − L0)"; }
};

class StateRecorder final : public runner::SessionObserver {
 public:
  void OnCommit(const runner::CommitEvent& e) override {
    if (e.kind == runner::RowKind::kCommitted) rows.emplace_back(e.x.begin(), e.x.end());
  }
  std::vector<std::vector<double>> rows;
};

std::vector<std::vector<double>> RunInMemory(io::RunSpec spec, runner::StepResult* result = nullptr) {
  spec.output.files = false;
  spec.quiet = true;
  runner::Session session(std::move(spec));
  StateRecorder recorder;
  session.AddObserver(recorder);
  const runner::StepResult r = session.Run();
  if (result != nullptr) {
    *result = r;
  } else {
    EXPECT_EQ(r.status, runner::SessionStatus::kFinished) << r.reason;
  }
  return recorder.rows;
}

double Worst(const std::vector<std::vector<double>>& a, const std::vector<std::vector<double>>& b,
             std::size_t column) {
  double worst = 0.0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    worst = std::max(worst, std::abs(a[i][column] - b[i][column]));
  }
  return worst;
}

TEST(RodSession, TwoActuatorBenchMatchesTheRodsNumericalTwin) {
  const auto physical = RunInMemory(io::LoadRunSpec(kExample + "large-displacement.yaml"));
  io::RunSpec twin = io::LoadRunSpec(kExample + "large-displacement.yaml");
  ASSERT_EQ(twin.substructures.size(), 1u);
  SubstructureSpec spec;
  spec.slot = "blade1";
  spec.slots = {"r_flap", "r_edge"};
  spec.custom = [] { return std::make_unique<RodTwin>(); };
  twin.substructures[0] = spec;
  const auto numerical = RunInMemory(std::move(twin));
  ASSERT_EQ(physical.size(), 10001u);
  ASSERT_EQ(numerical.size(), physical.size());
  double worst = 0.0, peak = 0.0;
  for (std::size_t j = 0; j < 4; ++j) worst = std::max(worst, Worst(physical, numerical, j));
  for (const auto& row : numerical) peak = std::max({peak, std::abs(row[0]), std::abs(row[1])});
  EXPECT_LT(worst, 1e-9);
  EXPECT_GT(peak, 0.02);  // [m] deflections of centimetres: the rods turn
  // The linear setup of the same J(0) is visibly wrong at these deflections.
  const auto linear = RunInMemory(io::LoadRunSpec(kExample + "large-displacement-linear.yaml"));
  const double flap = Worst(physical, linear, 0), edge = Worst(physical, linear, 1);
  std::cout << "[ q against the linear setup T = J(0): flap " << flap * 1e3 << " mm, edge "
            << edge * 1e3 << " mm; against the twin " << worst << " ]\n";
  EXPECT_GT(flap, 2e-3);
  EXPECT_GT(edge, 2e-3);
}

TEST(RodSession, DummyConfigIsTheSameTwin) {
  // dummy-large-displacement.yaml (a numerical block through the same setup) against the
  // test-local twin: the config's geometry is the example's.
  io::RunSpec spec = io::LoadRunSpec(kExample + "dummy-large-displacement.yaml");
  spec.scheme.duration = 2.0;
  spec.scheme.steps = 2000;
  io::RunSpec twin = spec;
  SubstructureSpec custom;
  custom.slot = "blade1";
  custom.slots = {"r_flap", "r_edge"};
  custom.custom = [] { return std::make_unique<RodTwin>(); };
  twin.substructures[0] = custom;
  const auto a = RunInMemory(std::move(spec)), b = RunInMemory(std::move(twin));
  ASSERT_EQ(a.size(), 2001u);
  for (std::size_t j = 0; j < 4; ++j) EXPECT_LT(Worst(a, b, j), 1e-12);
}

TEST(RodSession, SlotLimitStopsTheRunAndNamesTheSlot) {
  // The edge deflection reaches about 47 mm; a 30 mm limit on it stops the run there.
  const fs::path dir = test_support::FreshTempDir("hybridtest-rod-session");
  fs::create_directories(dir);
  std::ifstream in(kExample + "large-displacement.yaml");
  std::string text, line;
  while (std::getline(in, line)) text += line + "\n";
  const std::string from = "max_displacement: [0.08, 0.08]";
  ASSERT_NE(text.find(from), std::string::npos);
  text.replace(text.find(from), from.size(), "max_displacement: [0.08, 0.03]");
  for (const char* f : {"blade_tip.yaml", "bench-2act.yaml"}) {
    fs::copy_file(kExample + f, dir / f, fs::copy_options::overwrite_existing);
  }
  std::ofstream(dir / "limited.yaml") << text;
  runner::StepResult result;
  const auto rows = RunInMemory(io::LoadRunSpec((dir / "limited.yaml").string()), &result);
  EXPECT_EQ(result.status, runner::SessionStatus::kStopped);
  EXPECT_NE(result.reason.find("slot r_edge"), std::string::npos) << result.reason;
  EXPECT_NE(result.reason.find("max_displacement"), std::string::npos) << result.reason;
  ASSERT_FALSE(rows.empty());
  for (const auto& row : rows) EXPECT_LE(std::abs(row[1]), 0.03);
  fs::remove_all(dir);
}

TEST(RodSession, PlanJudgesTheSchemesAgainstTheRodsTwin) {
  // plan's reference is the bench's law seen through the rods, r = J(d)ᵀ F(ℓ(d) − L0): the
  // configured Heun at 1 ms is within 1 % of it (against the linear twin T0ᵀ K T0 it would be
  // several times the flap's peak-to-peak off).
  runner::PlanOptions options;
  options.seeds = {1};
  const auto results =
      runner::PlanTest(io::LoadRunSpec(kExample + "large-displacement.yaml"), options);
  ASSERT_FALSE(results.empty());
  ASSERT_TRUE(results[0].ok) << results[0].failure;
  EXPECT_EQ(results[0].evaluations, 20001);
  EXPECT_LT(results[0].error, 0.01);
  bool mr_os = false;
  for (const auto& r : results) {
    if (r.candidate.label.starts_with("mr-os") && r.ok && r.error < 0.01) mr_os = true;
  }
  EXPECT_TRUE(mr_os);
}

}  // namespace
}  // namespace hybridtest::substructures
