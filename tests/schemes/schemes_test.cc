// The hybrid schemes on a forced, damped linear oscillator whose spring is the "specimen"
// behind the seam: order of accuracy, evaluations per step, no repeated trial, and
// bit-identical continuation after SaveState/RestoreState.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <set>
#include <utility>

#include "hybridtest/common/error.h"
#include "hybridtest/integrators/catalogue.h"
#include "hybridtest/schemes/scheme_config.h"
#include "schemes/oscillator.h"
#include "support/alloc_counter.h"

namespace hybridtest::schemes {
namespace {

using testing::CollectRows;
using testing::Oscillator;
using testing::SpringSeam;

constexpr double kEnd = 1.0;  // [s]

struct SchemeRun {
  double q_end = 0.0;
  long steps = 0;
  std::vector<SpringSeam::Record> trials;
  std::vector<double> times;
};

SchemeConfig Config(SchemeKind kind, bool adaptive = false) {
  SchemeConfig c;
  c.kind = kind;
  c.adaptive.enabled = adaptive;
  c.adaptive.tolerance = 1e-7;
  c.adaptive.dt_min = 1e-4;
  c.adaptive.dt_max = 0.05;
  c.substep = 1e-4;
  return c;
}

std::unique_ptr<HybridScheme> Make(const multibody::Model& model, const SchemeConfig& c, double h,
                                   double k0) {
  SlotInfo slots{Eigen::VectorXd::Constant(1, k0),
                 Eigen::VectorXd::Constant(1, std::numeric_limits<double>::infinity()),
                 Eigen::MatrixXd()};
  return MakeScheme(c, integrators::FindTableau("rk4"), h, kEnd,
                    static_cast<long>(std::lround(kEnd / h)), model, slots);
}

// Runs from x0 = (0.01 m, 0) to kEnd; with `stop_after` > 0 the scheme is saved after that
// many steps, destroyed, and a new one restored from the saved state finishes the run.
SchemeRun Integrate(const Oscillator& o, const SchemeConfig& c, double h, double k0,
              long stop_after = 0) {
  const multibody::Model model = OscillatorModel(o);
  SpringSeam seam(o.k);
  CollectRows rows;
  auto scheme = Make(model, c, h, k0);
  Eigen::VectorXd x0(2), r0(1);
  x0 << 0.01, 0.0;
  seam.Trial({0, 0, 0.0}, x0.head(1), r0);
  scheme->Start(0.0, x0, r0);
  SchemeRun run;
  while (!scheme->finished()) {
    scheme->Step(seam, rows);
    rows.Row(scheme->committed().t, scheme->committed().x, scheme->committed().r);
    if (stop_after > 0 && scheme->committed().step == stop_after) {
      const std::string saved = scheme->SaveState().dump();
      scheme = Make(model, c, h, k0);
      scheme->RestoreState(nlohmann::json::parse(saved));
    }
  }
  run.q_end = scheme->committed().x(0);
  run.steps = scheme->committed().step;
  run.trials = seam.trials;
  run.times = rows.times;
  return run;
}

double Reference(const Oscillator& o) {
  return Integrate(o, Config(SchemeKind::kRungeKutta), 1e-5, o.k).q_end;
}

double ObservedOrder(const Oscillator& o, const SchemeConfig& c, double h, double k0) {
  const double ref = Reference(o);
  const double e1 = std::abs(Integrate(o, c, h, k0).q_end - ref);
  const double e2 = std::abs(Integrate(o, c, h / 2, k0).q_end - ref);
  return std::log2(e1 / e2);
}

TEST(AlphaOs, IsSecondOrderWithExactAndWithSoftK0) {
  const Oscillator o;
  EXPECT_NEAR(ObservedOrder(o, Config(SchemeKind::kAlphaOs), 0.01, o.k), 2.0, 0.25);
  EXPECT_NEAR(ObservedOrder(o, Config(SchemeKind::kAlphaOs), 0.01, 0.6 * o.k), 2.0, 0.25);
}

TEST(MrOs, IsExactUpToItsSubstepsWhenK0IsTheSpecimenStiffness) {
  // ρ ≡ 0: the macro step does not matter, only the RK4 substeps.
  const Oscillator o;
  const double ref = Reference(o);
  EXPECT_NEAR(Integrate(o, Config(SchemeKind::kMrOs), 0.05, o.k).q_end, ref, 1e-12);
}

TEST(MrOs, ConvergesInTheMacroStepWithAWrongK0) {
  const Oscillator o;
  EXPECT_GT(ObservedOrder(o, Config(SchemeKind::kMrOs), 0.02, 0.6 * o.k), 1.8);
}

TEST(Schemes, MakeTheirStatedEvaluationsPerStepAndNeverRepeatATrial) {
  const Oscillator o;
  for (const SchemeKind kind : {SchemeKind::kRungeKutta, SchemeKind::kAlphaOs, SchemeKind::kMrOs}) {
    const SchemeConfig c = Config(kind);
    const multibody::Model model = OscillatorModel(o);
    const int per_step = Make(model, c, 0.01, o.k)->evaluations_per_step();
    const SchemeRun run = Integrate(o, c, 0.01, 0.8 * o.k);
    // One initial trial, then exactly per_step per step.
    EXPECT_EQ(static_cast<long>(run.trials.size()), 1 + run.steps * per_step) << SchemeKindName(kind);
    std::set<std::pair<double, double>> seen;
    for (const auto& t : run.trials) {
      EXPECT_TRUE(seen.insert({t.t, t.d}).second)
          << SchemeKindName(kind) << ": trial repeated at t = " << t.t << ", d = " << t.d;
    }
  }
}

TEST(Schemes, AdaptiveStepsEndExactlyAtTheEndAndVary) {
  const Oscillator o;
  for (const SchemeKind kind : {SchemeKind::kAlphaOs, SchemeKind::kMrOs}) {
    const SchemeRun run = Integrate(o, Config(kind, true), 0.01, 0.8 * o.k);
    ASSERT_FALSE(run.times.empty());
    EXPECT_DOUBLE_EQ(run.times.back(), kEnd) << SchemeKindName(kind);
    std::set<double> sizes;
    double last = 0.0;
    for (const auto& t : run.trials) {
      if (t.t > last) sizes.insert(std::round((t.t - last) * 1e9));
      last = t.t;
    }
    EXPECT_GT(sizes.size(), 3u) << SchemeKindName(kind) << ": the step never changed";
  }
}

TEST(Schemes, AdaptiveErrorFollowsTheTolerance) {
  // A tighter tolerance buys accuracy with more steps (local error O(h³): tolerance / 8 halves
  // the steps' size, so the global error falls about fourfold).
  const Oscillator o;
  const double ref = Reference(o);
  for (const SchemeKind kind : {SchemeKind::kAlphaOs, SchemeKind::kMrOs}) {
    SchemeConfig loose = Config(kind, true);
    loose.adaptive.tolerance = 4e-7;
    SchemeConfig tight = loose;
    tight.adaptive.tolerance = 5e-8;
    const SchemeRun a = Integrate(o, loose, 0.01, 0.8 * o.k);
    const SchemeRun b = Integrate(o, tight, 0.01, 0.8 * o.k);
    EXPECT_GT(b.steps, a.steps) << SchemeKindName(kind);
    EXPECT_LT(std::abs(b.q_end - ref), 0.4 * std::abs(a.q_end - ref)) << SchemeKindName(kind);
  }
}

TEST(Schemes, ContinueBitIdenticallyAfterSaveAndRestore) {
  const Oscillator o;
  for (const bool adaptive : {false, true}) {
    for (const SchemeKind kind : {SchemeKind::kRungeKutta, SchemeKind::kAlphaOs, SchemeKind::kMrOs}) {
      if (adaptive && kind == SchemeKind::kRungeKutta) continue;
      const SchemeConfig c = Config(kind, adaptive);
      const SchemeRun straight = Integrate(o, c, 0.01, 0.8 * o.k);
      const SchemeRun resumed = Integrate(o, c, 0.01, 0.8 * o.k, 17);
      EXPECT_EQ(straight.q_end, resumed.q_end) << SchemeKindName(kind) << " adaptive=" << adaptive;
      EXPECT_EQ(straight.times, resumed.times) << SchemeKindName(kind);
    }
  }
}

// A step allocates nothing once the scheme is built (the seam and row sink here record into
// vectors with reserved room).
TEST(Schemes, StepsDoNotAllocate) {
  if (!test_support::kCanCountAllocations) GTEST_SKIP() << "allocations cannot be counted here";
  const Oscillator o;
  const multibody::Model model = OscillatorModel(o);
  for (const bool adaptive : {false, true}) {
    for (const SchemeKind kind : {SchemeKind::kRungeKutta, SchemeKind::kAlphaOs, SchemeKind::kMrOs}) {
      if (adaptive && kind == SchemeKind::kRungeKutta) continue;
      auto scheme = Make(model, Config(kind, adaptive), 0.01, 0.8 * o.k);
      SpringSeam seam(o.k);
      seam.trials.reserve(100000);
      CollectRows rows;
      rows.times.reserve(100000);
      rows.q.reserve(100000);
      Eigen::VectorXd x0(2), r0(1);
      x0 << 0.01, 0.0;
      seam.Trial({0, 0, 0.0}, x0.head(1), r0);
      scheme->Start(0.0, x0, r0);
      scheme->Step(seam, rows);  // warm-up
      const long allocations = test_support::CountAllocations([&] {
        for (int k = 0; k < 5 && !scheme->finished(); ++k) scheme->Step(seam, rows);
      });
      EXPECT_EQ(allocations, 0) << SchemeKindName(kind) << " adaptive=" << adaptive;
    }
  }
}

TEST(Schemes, RestoreRefusesAnotherSchemesState) {
  const Oscillator o;
  const multibody::Model model = OscillatorModel(o);
  auto rk = Make(model, Config(SchemeKind::kRungeKutta), 0.01, o.k);
  auto os = Make(model, Config(SchemeKind::kAlphaOs), 0.01, o.k);
  EXPECT_THROW(os->RestoreState(rk->SaveState()), Error);
}

}  // namespace
}  // namespace hybridtest::schemes
