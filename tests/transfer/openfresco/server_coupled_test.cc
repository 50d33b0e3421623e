// The OpenFresco server with a setup of two actuators predicts every actuator's force with the
// specimen's stiffness matrix K_a (the setup's, or BenchServerOptions::actuator_stiffness): a
// trial that moves only the soft actuator 2, harmless for each actuator on its own, is refused
// before anything moves because it loads the stiff actuator 1 through K12.
#include <gtest/gtest.h>

#include <optional>

#include "hybridtest/transfer/openfresco/server.h"
#include "transfer/bench_server_coupled_fake.h"
#include "transfer/openfresco/raw_peer.h"
#include "transfer/serving_thread.h"

namespace hybridtest::transfer::openfresco {
namespace {

using hybridtest::testing::RawPeer;
using transfer::testing::CoupledFakeBench;
using transfer::testing::CoupledStiffness;

const std::vector<std::int32_t> kHeader2{2, 2, 2, 0, 0, 0, 0, 0, 2, 0, 256};

// T = identity (2 × 2), p0 = 0, m and N on the wire, K_a the fake's specimen.
ExpSetup CoupledSetup() {
  ExpSetup s;
  s.wire_units = {1.0, 1.0, "m", "N"};
  s.actuators = 2;
  s.transform = {1.0, 0.0, 0.0, 1.0};
  s.p0s = {0.0, 0.0};
  const Eigen::Matrix2d k = CoupledStiffness();
  s.stiffness_matrix = {k(0, 0), k(0, 1), k(1, 0), k(1, 1)};
  return s;
}

// Trials d = (0, 1 mm), (0, 2 mm), then (0, 6 mm); each followed by getForce. Returns true if
// the server executed the third (it answered its getForce).
bool ThirdTrialExecuted(CoupledFakeBench& bench, std::optional<Eigen::MatrixXd> stiffness) {
  BenchServerOptions o;
  o.host = "127.0.0.1";
  o.port = 0;
  o.limits = {-0.15, 0.15, 0.005, 25.0, 50.0, 5.0};  // force_soft 25 N
  o.start_positions = {0.0, 0.0};
  o.actuator_stiffness = std::move(stiffness);
  Server server(bench, CoupledSetup(), o);
  transfer::testing::ServingThread<Server> serving(server);
  RawPeer peer(server.port());
  EXPECT_TRUE(peer.SendInts(kHeader2));
  bool executed = true;
  for (const double d2 : {0.001, 0.002, 0.006}) {
    EXPECT_TRUE(peer.SendDoubles({3, 0.0, d2, 0, 0, 0, 0}, 256));
    EXPECT_TRUE(peer.SendDoubles({10}, 256));
    const auto q = peer.ReadDoubles(256);
    executed = q.has_value();
    if (!executed) break;
    EXPECT_NEAR((*q)[0], 5000.0 * d2, 1e-9);
  }
  return executed;
}

TEST(OpenFrescoServerCoupled, TheSetupsStiffnessRefusesWhatEachActuatorAloneWouldPass) {
  CoupledFakeBench coupled;
  EXPECT_FALSE(ThirdTrialExecuted(coupled, std::nullopt));  // the setup's K_a
  EXPECT_EQ(coupled.executed(), 2) << "the refused trial moved the bench";

  // Each actuator on its own stiffness (the diagonal of K_a) passes the same trial.
  CoupledFakeBench scalar;
  const Eigen::MatrixXd diagonal = CoupledStiffness().diagonal().asDiagonal();
  EXPECT_TRUE(ThirdTrialExecuted(scalar, diagonal));
  EXPECT_EQ(scalar.executed(), 3);
}

}  // namespace
}  // namespace hybridtest::transfer::openfresco
