// AdsTransfer (transfer/ads/ads_transfer.h) against the TwinCAT PLC emulator (AdsServer) on
// 127.0.0.1, serving the ideal emulated benches of the examples: measurements equal those of
// the same bench in process (an independent path through the same physics), two round trips
// per exchange, and every refusal before anything moves and every fault mid-run.
#include <gtest/gtest.h>

#include <functional>

#include "hybridtest/common/error.h"
#include "transfer/ads/ads_support.h"

namespace hybridtest::transfer::ads {
namespace {

using testing::kIdealBench;
using testing::kTwoActuatorBench;
using testing::ServedPlc;

std::string Message(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(nothing thrown)";
}

// One command to a one-actuator transfer.
Measurement One(TransferSystem& t, double command) {
  Measurement m;
  t.Execute(std::span<const double>(&command, 1), std::span<Measurement>(&m, 1));
  return m;
}

// The commands of a short test in mm, for n actuators starting at `start` (mm each).
std::vector<std::vector<double>> Trajectory(const std::vector<double>& start) {
  std::vector<std::vector<double>> out;
  for (int i = 1; i <= 20; ++i) {
    std::vector<double> c;
    for (std::size_t k = 0; k < start.size(); ++k) {
      c.push_back(start[k] + 0.1 * i * static_cast<double>(k + 1) - 0.004 * i * i);
    }
    out.push_back(c);
  }
  return out;
}

void ExpectSameAsInProcess(const std::string& bench_file, int n, const std::vector<double>& start) {
  ServedPlc plc(bench_file);
  AdsTransfer ads(plc.Client(n));
  std::unique_ptr<TransferSystem> local = MakeEmulatedBench(plc.spec());
  ads.Activate();
  local->Activate();
  ASSERT_EQ(ads.num_actuators(), n);
  std::vector<Measurement> remote(static_cast<std::size_t>(n)), here(remote.size());
  for (const auto& commands : Trajectory(start)) {
    const long before = ads.requests();
    ads.Execute(commands, remote);
    EXPECT_EQ(ads.requests() - before, 2) << "one sum write and one sum read";
    local->Execute(commands, here);
    for (std::size_t k = 0; k < remote.size(); ++k) {
      EXPECT_EQ(remote[k].position, here[k].position) << "actuator " << k + 1;
      EXPECT_EQ(remote[k].force, here[k].force) << "actuator " << k + 1;
    }
  }
  EXPECT_GT(std::abs(here[0].force), 1.0) << "too little motion to test anything";
  ads.Deactivate();
  EXPECT_FALSE(ads.is_connected());
}

TEST(AdsTransfer, OneActuatorEqualsTheSameBenchInProcess) {
  ExpectSameAsInProcess(kIdealBench, 1, {20.0});
}

TEST(AdsTransfer, TwoActuatorsEqualTheSameBenchInProcess) {
  ExpectSameAsInProcess(kTwoActuatorBench, 2, {20.0, 30.0});
}

TEST(AdsTransfer, ReadAllAndProbeSeeThePlcWithoutMovingIt) {
  ServedPlc plc(kTwoActuatorBench);
  AdsTransfer probe(plc.Client(2));
  const auto reading = probe.Probe();
  ASSERT_TRUE(reading.has_value());
  EXPECT_EQ(reading->problem, "");
  ASSERT_EQ(reading->measurements.size(), 2u);
  EXPECT_DOUBLE_EQ(reading->measurements[0].position, 20.0);
  EXPECT_DOUBLE_EQ(reading->measurements[1].position, 30.0);
  EXPECT_NE(reading->status.find("not enabled"), std::string::npos) << reading->status;
  AdsTransfer ads(plc.Client(2));
  ads.Activate();
  const double commands[] = {21.0, 30.5};
  std::vector<Measurement> out(2);
  ads.Execute(commands, out);
  const auto now = ads.ReadAll();
  ASSERT_TRUE(now.has_value());
  EXPECT_EQ((*now)[0].position, 21.0);
  EXPECT_EQ((*now)[1].position, 30.5);
  EXPECT_EQ((*now)[1].force, out[1].force);
}

TEST(AdsTransfer, AMissingSymbolIsRefusedBeforeAnythingMovesNamingItAndTheFix) {
  ServedPlc plc(kIdealBench);
  AdsOptions o = plc.Client();
  o.profile.symbols[kForce] = "GVL_Hybrid.fLoad";
  AdsTransfer ads(o);
  const std::string m = Message([&] { ads.Activate(); });
  EXPECT_NE(m.find("has no symbol GVL_Hybrid.fLoad"), std::string::npos) << m;
  EXPECT_NE(m.find("0x710 (symbol not found)"), std::string::npos) << m;
  EXPECT_NE(m.find("fLoad : ARRAY [1..1] OF LREAL;"), std::string::npos) << m;
  EXPECT_NE(m.find("transfer.symbols.force"), std::string::npos) << m;
  // Issue 50: the section the message names exists ("The GVL" did not), and a mismatch of
  // the PLC project and the config is a configuration error (exit 2), not a transfer failure.
  EXPECT_NE(m.find("docs/ads.md, \"The profile\""), std::string::npos) << m;
  EXPECT_THROW(ads.Activate(), ConfigError);
  EXPECT_EQ(plc.server().commands_received(), 0);
}

// Issue 50: a PLC that does not answer was reported as "is `hybridtest bench` running there?".
TEST(AdsTransfer, APlcThatIsDownIsNamedAsAnAdsTarget) {
  AdsOptions o;
  {
    ServedPlc plc(kIdealBench);
    o = plc.Client();
  }  // the emulator is gone: its port refuses
  o.connect_timeout = 1.0;
  AdsTransfer ads(o);
  const std::string m = Message([&] { ads.Activate(); });
  EXPECT_NE(m.find("cannot connect to"), std::string::npos) << m;
  EXPECT_NE(m.find("(ADS"), std::string::npos) << m;
  EXPECT_NE(m.find("Routes and AmsNetIds"), std::string::npos) << m;
  EXPECT_EQ(m.find("hybridtest bench"), std::string::npos) << m;
}

TEST(AdsTransfer, AWrongTypeIsRefusedNamingTheSymbolAndBothTypes) {
  ServedPlc plc(kIdealBench);  // one actuator: ARRAY [1..1] OF LREAL
  AdsTransfer ads(plc.Client(2));
  const std::string m = Message([&] { ads.Activate(); });
  EXPECT_NE(m.find("symbol GVL_Hybrid.fCommand is ARRAY [1..1] OF LREAL (8 bytes), expected "
                   "ARRAY [1..2] OF LREAL (16 bytes)"), std::string::npos) << m;
  EXPECT_NE(m.find("nothing was moved"), std::string::npos) << m;
  EXPECT_THROW(ads.Activate(), ConfigError);  // issue 50: exit 2, the user's configuration
  EXPECT_EQ(plc.server().commands_received(), 0);
}

TEST(AdsTransfer, APlcInStopIsRefusedWithItsState) {
  ServedPlc plc(kIdealBench, [](AdsServerOptions& o) { o.ads_state = kStateStop; });
  AdsTransfer ads(plc.Client());
  const std::string m = Message([&] { ads.Activate(); });
  EXPECT_NE(m.find("is in STOP (ADS state 6), not RUN: nothing was moved"), std::string::npos) << m;
}

TEST(AdsTransfer, AnUnroutedClientIsClosedAndToldAboutRoutes) {
  ServedPlc plc(kIdealBench, [](AdsServerOptions& o) {
    o.routes = {ParseAdsRoute("192.168.0.5.1.1@127.0.0.1", "test")};
  });
  AdsTransfer ads(plc.Client());
  const std::string m = Message([&] { ads.Activate(); });
  EXPECT_NE(m.find("closed the connection instead of answering ReadState"), std::string::npos) << m;
  EXPECT_NE(m.find("add a route for AmsNetId 127.0.0.1.1.1"), std::string::npos) << m;
  // With the route's AmsNetId the same PLC answers.
  AdsOptions routed = plc.Client();
  routed.endpoint.local_net_id = ParseAmsNetId("192.168.0.5.1.1");
  AdsTransfer ok(routed);
  EXPECT_NO_THROW(ok.Activate());
}

TEST(AdsTransfer, AWrongAmsNetIdOrPortIsANamedAdsError) {
  ServedPlc plc(kIdealBench);
  AdsOptions o = plc.Client();
  o.endpoint.target.port = 852;
  AdsTransfer ads(o);
  const std::string m = Message([&] { ads.Activate(); });
  EXPECT_NE(m.find("0x6 (target port not found"), std::string::npos) << m;
}

// A fault injected at command 3 of a one-actuator run: the message, and the PLC holding.
std::string FaultAt(const std::string& kind, bool& holding_after) {
  ServedPlc plc(kIdealBench, [&](AdsServerOptions& o) { o.faults = {ParseAdsFault(kind + "@3", "test")}; });
  AdsOptions o = plc.Client();
  o.ack_timeout = 0.3;
  AdsTransfer ads(o);
  ads.Activate();
  std::string m;
  for (double c : {20.5, 21.0, 21.5}) {
    m = Message([&] { One(ads, c); });
  }
  AdsTransfer observer(plc.Client());
  const auto r = observer.Probe();
  holding_after = r && r->status.find(", holding") != std::string::npos;
  // The transfer refuses to move again until it is activated.
  EXPECT_THROW(One(ads, 21.5), TransferError);
  return m;
}

TEST(AdsTransfer, FaultsMidRunStopWithTheReasonAndThePlcHolding) {
  bool holding = false;
  std::string m = FaultAt("fault", holding);
  EXPECT_NE(m.find("reports a fault (GVL_Hybrid.bFault = TRUE)"), std::string::npos) << m;
  EXPECT_TRUE(holding);
  m = FaultAt("ads_error", holding);
  EXPECT_NE(m.find("ADS error 0x708 (device busy)"), std::string::npos) << m;
  EXPECT_NE(m.find("GVL_Hybrid.bHold was set"), std::string::npos) << m;
  EXPECT_TRUE(holding);
  m = FaultAt("silence", holding);
  EXPECT_NE(m.find("did not acknowledge within 0.3 s"), std::string::npos) << m;
  EXPECT_TRUE(holding);
  m = FaultAt("holding", holding);
  EXPECT_NE(m.find("reports holding (GVL_Hybrid.bHolding = TRUE)"), std::string::npos) << m;
  EXPECT_TRUE(holding);
  m = FaultAt("close", holding);
  EXPECT_NE(m.find("closed the connection instead of answering"), std::string::npos) << m;
  EXPECT_NE(m.find("the connection was lost"), std::string::npos) << m;
  EXPECT_TRUE(holding) << "the PLC holds when the client that drives it goes away";
}

TEST(AdsTransfer, ACommandTheEmulatorsGateRefusesFaultsThePlc) {
  ServedPlc plc(kIdealBench);
  AdsTransfer ads(plc.Client());
  ads.Activate();
  // 60 mm from 20 mm: beyond the bench's max_increment; the PLC refuses and faults.
  const std::string m = Message([&] { One(ads, 80.0); });
  EXPECT_NE(m.find("reports a fault"), std::string::npos) << m;
}

}  // namespace
}  // namespace hybridtest::transfer::ads
