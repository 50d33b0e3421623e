// A specimen on two actuators through the large-displacement setup (RodSetup) on the ideal
// two-actuator emulated bench: every trial against r = J(d)ᵀ K (ℓ(d) − L0) computed from the
// rods' points, the K0 ramp (J0ᵀ K J0), the increment bound, the numerical twin plan uses, and
// the limits per slot (refused before any actuator moves; a force stop names the slot).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "hybridtest/common/error.h"
#include "hybridtest/substructures/law_block.h"
#include "hybridtest/substructures/physical_substructure.h"
#include "hybridtest/substructures/rod_setup.h"
#include "hybridtest/substructures/substructure_spec.h"
#include "hybridtest/transfer/emulated_bench.h"

namespace hybridtest::substructures {
namespace {

const std::string kExample =
    std::string(HYBRIDTEST_SOURCE_DIR) + "/examples/06_blade_two_actuators/";

// The rods of examples/06_blade_two_actuators/large-displacement.yaml.
RodGeometry ExampleRods() {
  RodGeometry g;
  g.directions = Eigen::Matrix2d::Identity();
  g.bases.resize(2, 2);
  g.bases << -0.25, -0.15,
              0.0, -0.20;
  g.attachments = Eigen::Matrix2d::Zero();
  g.p0 = Eigen::Vector2d(0.02, 0.03);
  g.load_cell_zero = Eigen::Vector2d::Zero();
  return g;
}

// The oracle: r = J(d)ᵀ K (ℓ(d) − L0) from the points, J by central differences of ℓ.
Eigen::VectorXd OracleForces(const Eigen::VectorXd& d, const Eigen::MatrixXd& k) {
  const RodGeometry g = ExampleRods();
  auto lengths = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd {
    Eigen::VectorXd l(2);
    for (int j = 0; j < 2; ++j) {
      const Eigen::VectorXd rod = g.attachments.col(j) + x - g.bases.col(j);
      l(j) = std::sqrt(rod.dot(rod));
    }
    return l;
  };
  const Eigen::VectorXd f = k * (lengths(d) - lengths(Eigen::VectorXd::Zero(2)));
  Eigen::MatrixXd jac(2, 2);
  const double h = 1e-7;
  for (int i = 0; i < 2; ++i) {
    Eigen::VectorXd dp = d, dm = d;
    dp(i) += h;
    dm(i) -= h;
    jac.col(i) = (lengths(dp) - lengths(dm)) / (2.0 * h);
  }
  return jac.transpose() * f;
}

Eigen::MatrixXd BenchK() {
  Eigen::MatrixXd k(2, 2);
  k << 5000, 1200, 1200, 3000;
  return k;
}

std::unique_ptr<PhysicalSubstructure> MakeSpecimen(double max_increment = 0.005) {
  transfer::SafetyLimits limits;
  limits.max_increment = max_increment;
  return std::make_unique<PhysicalSubstructure>(
      "blade1",
      std::make_unique<transfer::EmulatedBench>(
          transfer::LoadEmulatedBenchSpec(kExample + "bench-2act.yaml")),
      std::make_unique<RodSetup>(ExampleRods()), std::vector{limits, limits});
}

// A path of slot displacements out to several centimetres, in steps the gate accepts.
std::vector<Eigen::VectorXd> Path() {
  std::vector<Eigen::VectorXd> out;
  for (int k = 0; k <= 80; ++k) {
    Eigen::VectorXd d(2);
    d << 0.06 * std::sin(0.05 * k), 0.04 * std::sin(0.08 * k + 0.3) - 0.04 * std::sin(0.3);
    out.push_back(d);
  }
  return out;
}

TEST(RodSubstructure, EveryTrialIsTheRodsViewOfTheSpecimen) {
  auto sub = MakeSpecimen();
  sub->Activate();
  double worst = 0.0, worst_linear = 0.0;
  const Eigen::MatrixXd t0 = sub->setup().linearisation();
  long step = 0;
  for (const auto& d : Path()) {
    Eigen::VectorXd r(2);
    sub->Trial({d.data(), 2}, {r.data(), 2}, {step++, 0, 0.0});
    sub->Commit();
    worst = std::max(worst, (r - OracleForces(d, BenchK())).cwiseAbs().maxCoeff());
    worst_linear = std::max(worst_linear, (r - t0.transpose() * BenchK() * t0 * d).cwiseAbs().maxCoeff());
    const RodSetup& rods = static_cast<const RodSetup&>(sub->setup());
    const Eigen::VectorXd a = ExampleRods().p0 + rods.CalcLengths(d) - rods.rest_lengths();
    EXPECT_NEAR(sub->actuator_exchange(0).command, a(0), 1e-15);
    EXPECT_NEAR(sub->actuator_exchange(1).command, a(1), 1e-15);
  }
  EXPECT_LT(worst, 1e-6);          // [N]; the oracle's J is a finite difference
  EXPECT_GT(worst_linear, 10.0);   // [N]; the geometry matters at these displacements
  std::cout << "[ largest slot force difference to the linear setup T = J(0): " << worst_linear
            << " N ]\n";
}

TEST(RodSubstructure, MeasuredK0IsTheLinearisedSpecimenStiffness) {
  auto sub = MakeSpecimen(0.002);
  sub->Activate();
  const auto m = sub->MeasureInitialStiffness(1e-3);
  Eigen::Matrix2d expected;  // J0ᵀ K J0 with J0 = [[1, 0], [0.6, 0.8]]
  expected << 7520.0, 2400.0, 2400.0, 1920.0;
  EXPECT_LT((m.k0 - expected).cwiseAbs().maxCoeff(), 1e-6 * 7520.0);
  // Slot steps of max_increment / √2 keep every rod's command step within max_increment.
  EXPECT_NEAR(sub->max_displacement_increment(), 0.002 / std::sqrt(2.0), 1e-15);
}

TEST(RodSubstructure, PlanTwinSeesTheGeometry) {
  auto sub = MakeSpecimen();
  const auto twin_spec = EmulatedBlockTwin(*sub);
  ASSERT_TRUE(twin_spec);
  ASSERT_TRUE(twin_spec->block_setup);
  EXPECT_FALSE(twin_spec->block_transform);
  auto twin = twin_spec->Build();
  sub->Activate();
  long step = 0;
  for (const auto& d : Path()) {
    Eigen::VectorXd r(2), rt(2);
    sub->Trial({d.data(), 2}, {r.data(), 2}, {step, 0, 0.0});
    twin->Trial({d.data(), 2}, {rt.data(), 2}, {step++, 0, 0.0});
    sub->Commit();
    twin->Commit();
    EXPECT_LT((r - rt).cwiseAbs().maxCoeff(), 1e-9);
  }
  Eigen::Matrix2d expected;
  expected << 7520.0, 2400.0, 2400.0, 1920.0;
  EXPECT_LT((*twin->initial_stiffness() - expected).cwiseAbs().maxCoeff(), 1e-9);
}

SlotLimits Limits(double max_d_edge, double max_f_flap) {
  SlotLimits l;
  l.names = {"r_flap", "r_edge"};
  l.max_displacement = Eigen::Vector2d(0.2, max_d_edge);
  l.max_force = Eigen::Vector2d(max_f_flap, 1e9);
  return l;
}

TEST(RodSubstructure, SlotDisplacementBeyondItsLimitIsRefusedBeforeAnyActuatorMoves) {
  auto sub = MakeSpecimen();
  sub->SetSlotLimits(Limits(0.01, 1e9));
  sub->Activate();
  Eigen::Vector2d d(0.002, 0.004), r;
  sub->Trial({d.data(), 2}, {r.data(), 2}, {0, 0, 0.0});
  const long moves = *sub->transfer().commands_received();
  d << 0.004, 0.0105;  // edge beyond 10 mm; each actuator's own step would pass
  try {
    sub->Trial({d.data(), 2}, {r.data(), 2}, {1, 0, 0.0});
    FAIL() << "no stop";
  } catch (const transfer::SafetyStop& e) {
    EXPECT_EQ(e.limit(), "slot_max_displacement");
    EXPECT_NE(std::string(e.what()).find("slot r_edge"), std::string::npos) << e.what();
    EXPECT_DOUBLE_EQ(e.value(), 0.0105);
  }
  EXPECT_EQ(*sub->transfer().commands_received(), moves);  // nothing was sent
  // A negative displacement beyond it is refused as well.
  d << 0.004, -0.011;
  EXPECT_THROW(sub->Trial({d.data(), 2}, {r.data(), 2}, {1, 1, 0.0}), transfer::SafetyStop);
  EXPECT_EQ(*sub->transfer().commands_received(), moves);
}

TEST(RodSubstructure, SlotForceBeyondItsLimitHoldsEveryActuatorAndNamesTheSlot) {
  auto sub = MakeSpecimen();
  sub->SetSlotLimits(Limits(0.2, 100.0));
  sub->Activate();
  Eigen::Vector2d d(0.004, 0.0), r;  // r_flap ≈ 7520 · 0.004 = 30 N
  sub->Trial({d.data(), 2}, {r.data(), 2}, {0, 0, 0.0});
  EXPECT_LT(std::abs(r(0)), 100.0);
  d << 0.008, 0.003;  // r_flap ≈ 67 N
  sub->Trial({d.data(), 2}, {r.data(), 2}, {1, 0, 0.0});
  EXPECT_LT(std::abs(r(0)), 100.0);
  d << 0.0115, 0.004;  // r_flap ≈ 96 N
  sub->Trial({d.data(), 2}, {r.data(), 2}, {2, 0, 0.0});
  EXPECT_LT(std::abs(r(0)), 100.0);
  d << 0.015, 0.004;  // r_flap ≈ 122 N
  try {
    sub->Trial({d.data(), 2}, {r.data(), 2}, {3, 0, 0.0});
    FAIL() << "no stop";
  } catch (const transfer::SafetyStop& e) {
    EXPECT_EQ(e.limit(), "slot_max_force");
    EXPECT_NE(std::string(e.what()).find("slot r_flap"), std::string::npos) << e.what();
    EXPECT_GT(e.value(), 100.0);
  }
  // Every actuator holds: the bench refuses the next move.
  const long moves = *sub->transfer().commands_received();
  d << 0.015, 0.004;
  EXPECT_ANY_THROW(sub->Trial({d.data(), 2}, {r.data(), 2}, {4, 0, 0.0}));
  EXPECT_EQ(*sub->transfer().commands_received(), moves);
}

TEST(RodSubstructure, SlotLimitsOfTheWrongSizeAreConfigErrors) {
  auto sub = MakeSpecimen();
  SlotLimits l = Limits(0.01, 100.0);
  l.max_force = Eigen::Vector3d(1, 2, 3);
  EXPECT_THROW(sub->SetSlotLimits(l), ConfigError);
  l = Limits(-0.01, 100.0);
  EXPECT_THROW(sub->SetSlotLimits(l), ConfigError);
}

}  // namespace
}  // namespace hybridtest::substructures
