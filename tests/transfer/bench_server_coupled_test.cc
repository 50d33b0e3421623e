// `hybridtest bench` serving several actuators predicts every actuator's force with the
// specimen's stiffness matrix (BenchServerOptions::actuator_stiffness): a command vector that
// moves only the soft actuator 2, harmless for each actuator on its own, is refused before
// anything moves because it loads the stiff actuator 1 through the coupling K12.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <vector>

#include "hybridtest/transfer/bench_client.h"
#include "hybridtest/transfer/bench_server.h"
#include "hybridtest/transfer/safety.h"
#include "transfer/bench_fake.h"
#include "transfer/bench_server_coupled_fake.h"

namespace hybridtest::transfer {
namespace {

using testing::CoupledFakeBench;
using testing::CoupledStiffness;

// force_soft 25 N: the moves below give at most 10 N; the third would give 30 N on actuator 1.
BenchServerOptions CoupledOptions(std::optional<Eigen::MatrixXd> stiffness) {
  BenchServerOptions o;
  o.host = "127.0.0.1";
  o.port = 0;
  o.limits = {-0.15, 0.15, 0.005, 25.0, 50.0, 5.0};
  o.start_positions = {0.0, 0.0};
  o.actuator_stiffness = std::move(stiffness);
  return o;
}

// Sends a = (0, 1 mm), (0, 2 mm), then (0, 6 mm) (a 4 mm move of actuator 2 only). Returns the
// refusal's limit of the third command, or "" if it was executed.
std::string ThirdMove(CoupledFakeBench& bench, std::optional<Eigen::MatrixXd> stiffness) {
  testing::ServerThread server(bench, CoupledOptions(std::move(stiffness)));
  BenchClient client(testing::ClientFor(server));
  client.Activate();
  EXPECT_EQ(client.num_actuators(), 2);
  std::vector<Measurement> out(2);
  client.Execute(std::vector<double>{0.0, 0.001}, out);
  client.Execute(std::vector<double>{0.0, 0.002}, out);
  EXPECT_NEAR(out[0].force, 10.0, 1e-12);  // K12 · 2 mm
  try {
    client.Execute(std::vector<double>{0.0, 0.006}, out);
  } catch (const SafetyStop& e) {
    EXPECT_NEAR(e.value(), 10.0 + 5000.0 * 0.004, 1e-9) << "f_last + K12 Δa2 on actuator 1";
    return e.limit();
  }
  return "";
}

TEST(BenchServerCoupled, CoupledPredictionRefusesWhatEachActuatorAloneWouldPass) {
  CoupledFakeBench coupled;
  EXPECT_EQ(ThirdMove(coupled, Eigen::MatrixXd(CoupledStiffness())), "force_soft");
  EXPECT_EQ(coupled.executed(), 2) << "the refused vector moved the bench";

  // Each actuator on its own (its own stiffness only: the diagonal) passes the same vector:
  // actuator 1 does not move, actuator 2 predicts 4 N + 2000 N/m · 4 mm = 12 N.
  CoupledFakeBench scalar;
  const Eigen::MatrixXd diagonal = CoupledStiffness().diagonal().asDiagonal();
  EXPECT_EQ(ThirdMove(scalar, diagonal), "");
  EXPECT_EQ(scalar.executed(), 3);
  CoupledFakeBench none;
  EXPECT_EQ(ThirdMove(none, std::nullopt), "");
  EXPECT_EQ(none.executed(), 3);
}

TEST(BenchServerCoupled, StiffnessOfTheWrongSizeIsAConfigError) {
  CoupledFakeBench bench;
  EXPECT_THROW(BenchServer(bench, CoupledOptions(Eigen::MatrixXd::Identity(3, 3))), ConfigError);
}

}  // namespace
}  // namespace hybridtest::transfer
