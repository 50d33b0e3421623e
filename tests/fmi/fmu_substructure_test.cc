// FMU substructures against independent oracles: the closed-form Maxwell element (trials
// rolled back to the committed state), the linear spring, unit conversion, a checkpoint.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "fmi/fmi_test_support.h"
#include "hybridtest/common/error.h"
#include "hybridtest/fmi/fmu_substructure.h"

namespace hybridtest::fmi {
namespace {

using test::EditedFmu;
using test::FmuSpec;
using test::TestFmu;

double TryOne(substructures::Substructure& s, double d, long step, int stage, double t) {
  double r = 0.0;
  const double dd[1] = {d};
  s.Trial(std::span<const double>(dd, 1), std::span<double>(&r, 1), {step, stage, t});
  return r;
}

// The Maxwell element: y(t + h) = x + (y − x) e^{−k h / c} with x held; F = k (x − y).
struct MaxwellOracle {
  double k, c, y = 0.0;
  double Trial(double x, double h) const { return k * (x - (x + (y - x) * std::exp(-k * h / c))); }
  void Commit(double x, double h) { y = x + (y - x) * std::exp(-k * h / c); }
};

// The same element as an FMI 2.0 and an FMI 3.0 FMU.
class StatefulFmu : public ::testing::TestWithParam<const char*> {};
INSTANTIATE_TEST_SUITE_P(FmiVersions, StatefulFmu, ::testing::Values("maxwell", "maxwell3"));

TEST_P(StatefulFmu, IsRolledBackBeforeEveryTrial) {
  const auto spec = FmuSpec("{type: fmu, fmu: " + TestFmu(GetParam()) +
                            ", displacement: x, force: F, parameters: {k: 7200, c: 50}}");
  auto s = spec.Build();
  ASSERT_EQ(s->num_slots(), 1);
  MaxwellOracle oracle{7200.0, 50.0};
  const double h = 0.001;
  double worst = 0.0;
  for (int n = 0; n < 200; ++n) {
    const double t = static_cast<double>(n) * h;
    const double x = 0.01 * std::sin(20.0 * t + 0.3);
    // Two stages per step (Heun): t_n with a junk displacement, then t_n + h.
    const double junk = TryOne(*s, 5.0 * x + 0.02, n, 0, t);
    EXPECT_NEAR(junk, oracle.Trial(5.0 * x + 0.02, 0.0), 1e-9);
    const double r = TryOne(*s, x, n, 1, t + h);
    worst = std::max(worst, std::abs(r - oracle.Trial(x, h)));
    s->Commit();
    oracle.Commit(x, h);
  }
  EXPECT_LT(worst, 1e-9);
  EXPECT_GT(std::abs(oracle.y), 1e-4);  // the dashpot moved: the state mattered
}

TEST(FmuSubstructure, StatelessSpringNeedsNoStateSupportAndMatchesKx) {
  const auto spec = FmuSpec("{type: fmu, fmu: " + TestFmu("spring") +
                            ", displacement: x, force: F, parameters: {k: 7200}, "
                            "initial_stiffness: 7200}");
  auto s = spec.Build();
  for (int n = 0; n < 50; ++n) {
    const double d = 0.001 * n - 0.02;
    EXPECT_DOUBLE_EQ(TryOne(*s, d, n, 0, n * 0.001), 7200.0 * d);
    EXPECT_DOUBLE_EQ(TryOne(*s, -d, n, 1, (n + 1) * 0.001), -7200.0 * d);
    s->Commit();
  }
  ASSERT_TRUE(s->initial_stiffness());
  EXPECT_EQ((*s->initial_stiffness())(0, 0), 7200.0);
}

// An FMU that speaks mm and kN: hybridtest converts at the seam (SI = factor · value).
TEST(FmuSubstructure, DeclaredUnitsAreConverted) {
  std::string fmu = EditedFmu("spring", R"(<Unit name="m"><BaseUnit m="1"/></Unit>)",
                              R"(<Unit name="m"><BaseUnit m="1" factor="0.001"/></Unit>)",
                              "spring_mm.fmu");
  const auto spec = FmuSpec("{type: fmu, fmu: " + fmu +
                            ", displacement: x, force: F, parameters: {k: 7.2}}");
  auto s = spec.Build();
  // x = 10 mm, F = 7.2 · 10 = 72 (the FMU's force unit is N): r = 72 N.
  EXPECT_NEAR(TryOne(*s, 0.01, 0, 0, 0.0), 72.0, 1e-12);
}

TEST_P(StatefulFmu, CheckpointContinuesBitIdentically) {
  const auto spec = FmuSpec("{type: fmu, fmu: " + TestFmu(GetParam()) +
                            ", displacement: x, force: F, parameters: {k: 7200, c: 50}}");
  auto a = spec.Build();
  const double h = 0.001;
  for (int n = 0; n < 30; ++n) {
    TryOne(*a, 0.001 * n, n, 0, (n + 1) * h);
    a->Commit();
  }
  const nlohmann::json saved = a->SaveState();
  ASSERT_TRUE(saved.contains("fmu_state"));
  auto b = spec.Build();
  b->RestoreState(saved);
  for (int n = 30; n < 60; ++n) {
    const double x = 0.001 * std::cos(0.1 * n);
    EXPECT_EQ(TryOne(*a, x, n, 0, (n + 1) * h), TryOne(*b, x, n, 0, (n + 1) * h));
    a->Commit();
    b->Commit();
  }
}

// fail_at: fmi2DoStep returns fmi2Error; the trial throws TransferError with the FMU's words.
TEST_P(StatefulFmu, ErrorStatusIsATransferErrorWithTheFmusLog) {
  const std::string id = GetParam();
  const std::string version = id == "maxwell3" ? "fmi3" : "fmi2";
  const auto spec = FmuSpec("{type: fmu, fmu: " + TestFmu(id) +
                            ", displacement: x, force: F, parameters: {fail_at: 0.0025}}");
  std::vector<std::string> logged;
  auto s = spec.Build();
  TryOne(*s, 0.001, 0, 0, 0.001);
  s->Commit();
  TryOne(*s, 0.001, 1, 0, 0.002);
  s->Commit();
  try {
    TryOne(*s, 0.001, 2, 0, 0.003);
    FAIL() << "no error";
  } catch (const TransferError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(id + ".fmu"), std::string::npos) << what;
    EXPECT_NE(what.find(version + "DoStep"), std::string::npos) << what;
    EXPECT_NE(what.find(version + "Error"), std::string::npos) << what;
    EXPECT_NE(what.find("fail_at reached: the step ends at 0.003 s"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace hybridtest::fmi
