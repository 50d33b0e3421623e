// Resume of a specimen on two actuators (PhysicalSubstructure::ReimposeCommitted): the
// actuators are read where they are, walked back together in moves within every
// max_increment, and the committed commands re-imposed; a specimen that no longer carries the
// committed forces is refused with the actuator named.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "hybridtest/substructures/physical_substructure.h"
#include "hybridtest/transfer/emulated_bench.h"

namespace hybridtest::substructures {
namespace {

const std::string kExample =
    std::string(HYBRIDTEST_SOURCE_DIR) + "/examples/06_blade_two_actuators/";
constexpr double kMaxIncrement = 0.005;  // [m], as the example bench's own limit

struct Rig {
  transfer::EmulatedBench* bench = nullptr;  // owned by specimen
  std::unique_ptr<PhysicalSubstructure> specimen;
};

Rig MakeRig(const std::string& bench_file) {
  LinearSetup setup;
  setup.p0 = Eigen::Vector2d(0.02, 0.03);
  setup.transform.resize(2, 2);
  setup.transform << 1.0, 0.0, 0.6, 0.8;
  setup.load_cell_zero = Eigen::Vector2d::Zero();
  transfer::SafetyLimits limits;
  limits.max_increment = kMaxIncrement;
  auto bench = std::make_unique<transfer::EmulatedBench>(
      transfer::LoadEmulatedBenchSpec(kExample + bench_file));
  Rig rig;
  rig.bench = bench.get();
  rig.specimen = std::make_unique<PhysicalSubstructure>(
      "blade1", std::move(bench), std::move(setup), std::vector{limits, limits});
  rig.specimen->Activate();
  return rig;
}

// Drives the specimen along slot displacements (out to `peak` and back to `end`, in steps the
// gate accepts) and returns its state with the bench's own state dropped: a restored run whose
// bench came back at p0, where a lab would find an actuator that was moved by hand.
nlohmann::json RunAndSave(PhysicalSubstructure& s, double peak, double end) {
  std::vector<double> path;
  for (int k = 1; k <= 40; ++k) path.push_back(peak * k / 40.0);
  for (int k = 1; k <= 30; ++k) path.push_back(peak + (end - peak) * k / 30.0);
  long step = 0;
  for (double x : path) {
    const double d[2] = {x, -0.5 * x};
    double r[2];
    s.Trial(d, r, {++step, 0, 0.001 * static_cast<double>(step)});
  }
  nlohmann::json state = s.SaveState();
  state["transfer"] = nullptr;
  return state;
}

TEST(MultiActuatorResume, WalksBackFromWhereTheActuatorsAreWithinEveryIncrement) {
  Rig a = MakeRig("bench-2act.yaml");
  const nlohmann::json state = RunAndSave(*a.specimen, 0.03, 0.03);
  Rig b = MakeRig("bench-2act.yaml");
  b.specimen->RestoreState(state);
  std::vector<std::vector<double>> positions{{b.bench->actuator_position(0),
                                              b.bench->actuator_position(1)}};
  int ramps = 0, reimpositions = 0;
  const auto check = b.specimen->ReimposeCommitted(0.0, 0.0, 30, [&](bool reimposition) {
    (reimposition ? reimpositions : ramps) += 1;
    positions.push_back({b.bench->actuator_position(0), b.bench->actuator_position(1)});
  });
  ASSERT_EQ(check.actuators.size(), 2U);
  // Actuator 1 is 30 mm from p0, actuator 2 (0.6 − 0.8 · 0.5) · 30 = 6 mm: seven moves.
  EXPECT_EQ(check.ramp_moves, 6);
  EXPECT_EQ(ramps, 6);
  EXPECT_EQ(reimpositions, 1);
  for (std::size_t j = 1; j < positions.size(); ++j) {
    for (std::size_t k = 0; k < 2; ++k) {
      EXPECT_LT(std::abs(positions[j][k] - positions[j - 1][k]), kMaxIncrement) << j << " " << k;
    }
  }
  const double p0[2] = {0.02, 0.03};
  for (std::size_t k = 0; k < 2; ++k) {
    const auto& c = check.actuators[k];
    ASSERT_TRUE(c.read_position.has_value());
    EXPECT_NEAR(*c.read_position, p0[k], 1e-12);
    EXPECT_NEAR(*c.read_force, 0.0, 1e-9);
    EXPECT_NEAR(c.position, c.command, 1e-12);
    EXPECT_NEAR(c.force, c.committed_force, 1e-9);
    EXPECT_DOUBLE_EQ(c.position_tolerance, 0.25 * kMaxIncrement);
  }
  // The committed commands are the path's last: a = p0 + T d with d = (0.03, −0.015).
  EXPECT_NEAR(check.actuators[0].command, 0.05, 1e-12);
  EXPECT_NEAR(check.actuators[1].command, 0.03 + 0.6 * 0.03 - 0.8 * 0.015, 1e-12);
}

// A yielding specimen loaded out and back keeps a residual state; the restarted bench's
// specimen is virgin, so at the committed commands it carries other forces: refused, with
// the actuator named, and every actuator holds.
TEST(MultiActuatorResume, AChangedSpecimenIsRefusedWithTheActuatorNamed) {
  Rig a = MakeRig("bench-2act-bouc-wen.yaml");
  const nlohmann::json state = RunAndSave(*a.specimen, 0.1, 0.01);
  Rig b = MakeRig("bench-2act-bouc-wen.yaml");
  b.specimen->RestoreState(state);
  // With K0 known, the default force tolerance is K_a,kk times the position tolerance
  // (5000 N/m · 1.25 mm = 6.25 N for actuator 1), not 1 % of force_hard (100 N, more than
  // this specimen's yield force of 75 N).
  Eigen::MatrixXd t(2, 2), ka = Eigen::Vector2d(5000, 3000).asDiagonal();
  t << 1.0, 0.0, 0.6, 0.8;
  b.specimen->SetInitialStiffness(t.transpose() * ka * t);
  try {
    b.specimen->ReimposeCommitted(0.0, 0.0, 30, {});
    FAIL() << "a specimen with another history was accepted";
  } catch (const transfer::SafetyStop& e) {
    EXPECT_EQ(e.limit(), "resume_force_tolerance");
    EXPECT_NE(std::string(e.what()).find("actuator "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("Every actuator holds"), std::string::npos);
  }
}

}  // namespace
}  // namespace hybridtest::substructures
