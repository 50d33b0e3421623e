// The OpenFresco server with a setup of two actuators (T 2 × 4) on the two-actuator emulated
// bench of examples/06_blade_two_actuators: action 10 answers q = Tᵀ f, action 13 Tᵀ K T
// (column-major), action 7 a displacement whose T d_m is the measured offset, and a trial
// that one actuator may not take moves neither.
#include <gtest/gtest.h>

#include <cmath>

#include "hybridtest/transfer/emulated_bench.h"
#include "hybridtest/transfer/openfresco/server.h"
#include "transfer/openfresco/raw_peer.h"
#include "transfer/serving_thread.h"

namespace hybridtest::transfer::openfresco {
namespace {

using hybridtest::testing::RawPeer;

const std::string kBench =
    HYBRIDTEST_SOURCE_DIR "/examples/06_blade_two_actuators/bench-2act.yaml";
const std::vector<std::int32_t> kHeader4{4, 4, 4, 0, 0, 0, 0, 0, 4, 0, 256};
// T (2 × 4), row-major; K in actuator coordinates [N/mm] (the bench's, mm and N on the wire).
const double kT[2][4] = {{0.6, -0.8, -0.6, 0.8}, {0.0, 1.0, 0.0, -1.0}};
const double kK[2][2] = {{5.0, 1.2}, {1.2, 3.0}};

struct Fixture {
  EmulatedBenchSpec config = LoadEmulatedBenchSpec(kBench);
  EmulatedBench bench{config};
  Server server{bench, Setup(), Options()};
  transfer::testing::ServingThread<Server> serving{server};

  ExpSetup Setup() const {
    ExpSetup s;
    s.actuators = 2;
    for (const auto& row : kT) s.transform.insert(s.transform.end(), row, row + 4);
    s.p0s = {config.actuators[0].p0, config.actuators[1].p0};
    for (int i = 0; i < 2; ++i) {
      for (int j = 0; j < 2; ++j) s.stiffness_matrix.push_back(config.stiffness(i, j));
    }
    return s;
  }
  BenchServerOptions Options() const {
    BenchServerOptions o;
    o.host = "127.0.0.1";
    o.port = 0;
    o.limits = config.actuators[0].safety;
    o.start_positions = {config.actuators[0].initial_position, config.actuators[1].initial_position};
    return o;
  }
};

TEST(OpenFrescoMultiActuator, ForcesAndStiffnessThroughTheTransform) {
  Fixture f;
  RawPeer peer(f.server.port());
  ASSERT_TRUE(peer.SendInts(kHeader4));
  const double d[4] = {0.5, 1.0, -0.25, -0.5};  // [mm]
  ASSERT_TRUE(peer.SendDoubles({3, d[0], d[1], d[2], d[3], 0, 0, 0, 0, 0, 0, 0, 0}, 256));
  double x[2] = {0.0, 0.0};  // T d [mm]
  for (int k = 0; k < 2; ++k) {
    for (int i = 0; i < 4; ++i) x[k] += kT[k][i] * d[i];
  }
  double force[2] = {0.0, 0.0};  // K x [N]
  for (int k = 0; k < 2; ++k) force[k] = kK[k][0] * x[0] + kK[k][1] * x[1];
  ASSERT_TRUE(peer.SendDoubles({10}, 256));
  const auto q = peer.ReadDoubles(256);
  ASSERT_TRUE(q);
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR((*q)[i], kT[0][i] * force[0] + kT[1][i] * force[1], 1e-9) << i;
  }
  ASSERT_TRUE(peer.SendDoubles({13}, 256));
  const auto kd = peer.ReadDoubles(256);
  ASSERT_TRUE(kd);
  for (int col = 0; col < 4; ++col) {
    for (int row = 0; row < 4; ++row) {
      double expected = 0.0;
      for (int a = 0; a < 2; ++a) {
        for (int b = 0; b < 2; ++b) expected += kT[a][row] * kK[a][b] * kT[b][col];
      }
      EXPECT_NEAR((*kd)[col * 4 + row], expected, 1e-12) << row << "," << col;
    }
  }
  for (int i = 16; i < 256; ++i) EXPECT_EQ((*kd)[i], 0.0);
  ASSERT_TRUE(peer.SendDoubles({7}, 256));
  const auto dm = peer.ReadDoubles(256);
  ASSERT_TRUE(dm);
  for (int k = 0; k < 2; ++k) {
    double tdm = 0.0;
    for (int i = 0; i < 4; ++i) tdm += kT[k][i] * (*dm)[i];
    EXPECT_NEAR(tdm, x[k], 1e-9) << k;
  }
  ASSERT_TRUE(peer.SendDoubles({6}, 256));
  const auto daq = peer.ReadDoubles(256);
  ASSERT_TRUE(daq);
  // sizeDaq has only the force block (4): the actuators' forces [N], then zeros.
  EXPECT_NEAR((*daq)[0], force[0], 1e-9);
  EXPECT_NEAR((*daq)[1], force[1], 1e-9);
  EXPECT_EQ((*daq)[2], 0.0);
  ASSERT_TRUE(peer.SendDoubles({99}, 256));
  EXPECT_EQ(f.server.trials_executed(), 1);
}

TEST(OpenFrescoMultiActuator, OneRefusedActuatorMovesNeither) {
  Fixture f;
  RawPeer peer(f.server.port());
  ASSERT_TRUE(peer.SendInts(kHeader4));
  // Actuator 2 would move 10 mm (T row 2 · d), beyond the 5 mm increment; actuator 1 none.
  ASSERT_TRUE(peer.SendDoubles({3, 0, 5.0, -40.0 / 3.0, -5.0, 0, 0, 0, 0, 0, 0, 0, 0}, 256));
  EXPECT_TRUE(peer.ClosedByPeer());
  EXPECT_EQ(*f.bench.commands_received(), 0);
  EXPECT_NEAR(f.bench.actuator_position(0), f.config.actuators[0].p0, 1e-15);
  EXPECT_NEAR(f.bench.actuator_position(1), f.config.actuators[1].p0, 1e-15);
}

}  // namespace
}  // namespace hybridtest::transfer::openfresco
