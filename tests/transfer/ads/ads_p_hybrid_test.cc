// The PLC side of docs/ads.md: the emulator running the docs' Structured Text P_Hybrid
// (PlcProgram::kPHybrid) through what hybridtest does to a PLC — probe, run, Hold, resume —
// and its heartbeat watchdog setting the hold when hybridtest stops beating; and the docs'
// global variable list, read from docs/ads.md, against the emulator's symbol table.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <sstream>
#include <thread>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/ads/ads_plc_image.h"
#include "transfer/ads/ads_support.h"

namespace hybridtest::transfer::ads {
namespace {

using testing::kIdealBench;
using testing::ServedPlc;

Measurement Move(AdsTransfer& t, double command) {
  Measurement m;
  t.Execute(std::span<const double>(&command, 1), std::span<Measurement>(&m, 1));
  return m;
}

std::string Failure(AdsTransfer& t, double command) {
  try {
    Move(t, command);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(nothing thrown)";
}

// A reader that writes nothing (no heartbeat either): what the PLC shows now.
ProbeReading Look(const ServedPlc& plc) {
  AdsTransfer reader(plc.Client());
  return *reader.Probe();
}

// Whether the PLC comes to show holding within 10 s (it does so on its next cycle, or when
// its watchdog expires).
bool ComesToHold(const ServedPlc& plc) {
  for (int i = 0; i < 400; ++i) {
    if (Look(plc).status.find(", holding") != std::string::npos) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(25));
  }
  return false;
}

TEST(AdsPHybrid, ProbeRunHoldResumeAndTheWatchdogHoldsWhenTheHeartbeatStops) {
  ServedPlc plc(kIdealBench, [](AdsServerOptions& o) {
    o.program = PlcProgram::kPHybrid;
    o.watchdog = 1.0;
  });
  // probe: live values while idle and not enabled; nothing written.
  ProbeReading seen = Look(plc);
  EXPECT_EQ(seen.problem, "");
  ASSERT_EQ(seen.measurements.size(), 1u);
  EXPECT_DOUBLE_EQ(seen.measurements[0].position, 20.0);
  EXPECT_NE(seen.status.find("not enabled"), std::string::npos) << seen.status;

  // run: every command acknowledged a cycle after its move, with the bench's measurement.
  AdsOptions options = plc.Client();
  options.poll_interval = 0.002;
  AdsTransfer ads(options);
  std::unique_ptr<TransferSystem> local = MakeEmulatedBench(plc.spec());
  ads.Activate();
  local->Activate();
  for (int i = 1; i <= 5; ++i) {
    const double command = 20.0 + 0.2 * i;
    const Measurement remote = Move(ads, command);
    Measurement here;
    local->Execute(std::span<const double>(&command, 1), std::span<Measurement>(&here, 1));
    EXPECT_EQ(remote.position, here.position) << "command " << i;
    EXPECT_EQ(remote.force, here.force) << "command " << i;
  }
  EXPECT_EQ(plc.server().commands_received(), 5);

  // Hold: the PLC holds and takes no command; resume (Activate) releases it.
  ads.Hold();
  EXPECT_TRUE(ComesToHold(plc));
  ads.Activate();
  EXPECT_DOUBLE_EQ(Move(ads, 21.5).position, 21.5);

  // hybridtest stops writing the heartbeat (it computes, hangs, or its cable is pulled; the
  // connection stays open): the watchdog sets bHold.
  ASSERT_TRUE(ComesToHold(plc)) << "the watchdog never set the hold in 10 s";
  const std::string refused = Failure(ads, 22.0);
  EXPECT_NE(refused.find("reports holding"), std::string::npos) << refused;

  // resume: Activate clears the hold; the command sent while held is dropped, never run.
  ads.Activate();
  const auto now = ads.ReadAll();
  ASSERT_TRUE(now.has_value());
  EXPECT_DOUBLE_EQ((*now)[0].position, 21.5) << "the command sent while held was executed";
  EXPECT_DOUBLE_EQ(Move(ads, 21.8).position, 21.8);
  EXPECT_EQ(plc.server().commands_received(), 7);
  ads.Deactivate();
}

// The docs' VAR_GLOBAL block, as (name, type) in order of declaration.
std::vector<std::pair<std::string, std::string>> DocsGlobals() {
  std::ifstream in(std::string(HYBRIDTEST_SOURCE_DIR) + "/docs/ads.md");
  std::stringstream text;
  text << in.rdbuf();
  const std::string doc = text.str();
  const auto begin = doc.find("VAR_GLOBAL");
  const auto end = doc.find("END_VAR", begin);
  std::vector<std::pair<std::string, std::string>> out;
  if (begin == std::string::npos || end == std::string::npos) return out;
  std::istringstream block(doc.substr(begin, end - begin));
  const std::regex declaration(R"(^\s*(\w+)\s*:\s*([^;]+);)");
  std::string line;
  while (std::getline(block, line)) {
    line = line.substr(0, line.find("//"));  // a comment
    std::smatch m;
    if (std::regex_search(line, m, declaration)) out.emplace_back(m[1].str(), m[2].str());
  }
  return out;
}

TEST(AdsPHybrid, TheDocsGlobalVariableListIsTheEmulatorsSymbolTable) {
  const auto globals = DocsGlobals();
  const PlcImage image(DefaultProfile(2));  // the docs declare n = 2
  ASSERT_EQ(globals.size(), std::size_t{kNumRoles}) << "docs/ads.md's VAR_GLOBAL";
  for (std::size_t r = 0; r < kNumRoles; ++r) {
    const SymbolInfo& s = image.symbol(static_cast<Role>(r));
    EXPECT_EQ("GVL_Hybrid." + globals[r].first, s.name);
    EXPECT_EQ(NormaliseTypeName(globals[r].second), NormaliseTypeName(s.type)) << s.name;
  }
}

}  // namespace
}  // namespace hybridtest::transfer::ads
