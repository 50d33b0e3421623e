// The real-time plant served over TCP (`hybridtest bench --real-time`): it runs on the
// SERVER's clock between commands, and a paced client's commands are answered at once with
// the measurement of that moment. The server's clock here is virtual and advanced by the test,
// so the delayed response is seen exactly: a command reaches the position only once the
// server's clock has passed the plant's delay, however often the client asks.
#include <gtest/gtest.h>

#include "hybridtest/common/clock.h"
#include "hybridtest/transfer/bench_client.h"
#include "hybridtest/transfer/rt_plant.h"
#include "transfer/bench_fake.h"

namespace hybridtest::transfer {
namespace {

using testing::ClientFor;
using testing::ServerThread;

TEST(RtPlantServed, ThePlantRunsOnTheServersClockBetweenCommands) {
  RtPlantConfig config;
  config.kind = PlantKind::kIdeal;
  config.one().delay = 0.005;  // [s]
  config.specimen.stiffness = {1000.0};
  RtPlant plant(config);
  VirtualClock server_clock;
  plant.StartPaced(0.001, server_clock);
  BenchServerOptions options;
  options.limits.stroke_min = -0.1;
  options.limits.stroke_max = 0.1;
  options.limits.max_increment = 0.05;
  options.limits.force_soft = 1e4;
  options.limits.force_hard = 2e4;
  options.start_position = 0.0;
  ServerThread server(plant, options);
  BenchClient client(ClientFor(server));
  client.Activate();
  VirtualClock client_clock;
  client.StartPaced(0.001, client_clock);  // the client's clock paces nothing remote

  // t = 0: the command is sent; the delayed plant has not moved.
  Measurement m = ExecuteOne(client, 0.01);
  EXPECT_EQ(m.position, 0.0);
  // Asked again at the same server time: still not moved (commands do not advance it).
  for (int i = 0; i < 5; ++i) EXPECT_EQ(ExecuteOne(client, 0.01).position, 0.0);
  // The server's clock passes the delay: the position and force follow.
  server_clock.WaitUntil(0.0061);
  m = ExecuteOne(client, 0.01);
  EXPECT_DOUBLE_EQ(m.position, 0.01);
  EXPECT_NEAR(m.force, 1000.0 * 0.01, 1e-9);
  EXPECT_FALSE(server.failed());
  client.Deactivate();
}

}  // namespace
}  // namespace hybridtest::transfer
