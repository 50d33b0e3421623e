// The start of every run is checked at the bench (issue 45, item 1; docs/safety.md, "Checks
// before a run starts"). The contract: two runs of the same config in a row against one
// server (the ADS PLC emulator, the bench protocol's server, the pymodbus controller): the
// first leaves the actuator away from p0, the second refuses before moving (exit 3, the
// position read and p0 in its message, the server received no command) and, with
// `start: ramp`, ramps there in moves within max_increment and finishes. Each run is
// shortened to kDuration (a test config beside the run).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "hybridtest/io/run_reader.h"
#include "integration/bench_process.h"
#include "integration/resume_support.h"
#include "transfer/modbus_server_process.h"

namespace hybridtest::testing {
namespace {

// Long enough for the rotor's blade 1 to leave the actuator more than max_increment (5 mm;
// 2 mm for modbus.yaml) from p0.
constexpr const char* kDuration = "duration: 0.4";

// `example` (a config of examples/rotor) with its duration shortened, and `extra` appended.
fs::path TestConfig(const fs::path& dir, const std::string& example, const std::string& name,
                    const std::string& extra) {
  std::ifstream in(kSource + "/examples/rotor/" + example);
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  const auto at = yaml.find("duration: 10.0");
  EXPECT_NE(at, std::string::npos);
  yaml.replace(at, 14, kDuration);
  const fs::path config = dir / (name + ".yaml");
  std::ofstream(config) << yaml << "\n" << extra;
  return config;
}

struct Outcome {
  int status = -1;
  std::string output;
  nlohmann::json start;  // the sidecar's statistics.start
};

Outcome Run(const fs::path& dir, const fs::path& config, const std::string& name,
            const std::string& bench) {
  const fs::path csv = dir / (name + ".csv");
  Child child(HybridtestArgv(RunArgs(config.string(), csv, bench)), dir / (name + ".log"));
  Outcome o;
  o.status = child.WaitExit(120.0);
  o.output = child.output();
  if (fs::exists(csv)) {
    const io::RunData data = io::LoadRun(csv.string());
    o.start = data.metadata.value("statistics", nlohmann::json::object())
                  .value("start", nlohmann::json());
  }
  return o;
}

// The contract against one server at `bench`: `example` twice, then with `start: ramp`.
// `p0_text` is how the message names p0.
void TwoRunsInARow(const std::string& example, const std::string& bench,
                   const std::string& name, const std::string& p0_text, double max_increment) {
  const fs::path dir = ResumeTestDir("start-" + name);
  const fs::path plain = TestConfig(dir, example, "plain", "");
  // The first run starts at p0 and leaves the actuator where its blade went.
  const Outcome first = Run(dir, plain, "first", bench);
  ASSERT_EQ(first.status, 0) << first.output;
  ASSERT_TRUE(first.start.is_array() && first.start.size() == 1) << first.start;
  EXPECT_EQ(first.start[0]["read"], true) << first.start;
  EXPECT_EQ(first.start[0]["ramp_moves"], 0);
  // The second refuses before moving.
  const Outcome second = Run(dir, plain, "second", bench);
  EXPECT_EQ(second.status, 3) << second.output;
  EXPECT_NE(second.output.find("the actuator is at"), std::string::npos) << second.output;
  EXPECT_NE(second.output.find(p0_text), std::string::npos) << second.output;
  EXPECT_NE(second.output.find("start: ramp"), std::string::npos) << second.output;
  // With `start: ramp`, it ramps within max_increment and finishes.
  const Outcome third = Run(dir, TestConfig(dir, example, "ramp", "start: ramp\n"), "third", bench);
  ASSERT_EQ(third.status, 0) << third.output;
  ASSERT_TRUE(third.start.is_array() && third.start.size() == 1) << third.start;
  const nlohmann::json& a = third.start[0]["actuators"][0];
  const double gap = a["gap_m"].get<double>();
  std::cout << "[ " << name << ": the second run found the actuator " << gap * 1e3
            << " mm from its first command; ramped in " << third.start[0]["ramp_moves"]
            << " moves ]\n";
  EXPECT_GT(gap, max_increment);
  EXPECT_EQ(third.start[0]["ramp_moves"].get<int>(),
            static_cast<int>(std::ceil(gap / (0.999 * max_increment))));
  fs::remove_all(dir);
}

TEST(StartCheck, ContractAdsSecondRunRefusesThenRamps) {
  BenchProcess plc({"--protocol", "ads", "--config", kSource + "/examples/rotor/bench-ideal.yaml"});
  TwoRunsInARow("ads.yaml", fmt::format("127.0.0.1:{}", plc.port()), "ads",
                "p0 = 0.02 m (20 mm)", 0.005);
}

TEST(StartCheck, ContractBenchProtocolSecondRunRefusesThenRamps) {
  BenchProcess bench({"--config", kSource + "/examples/rotor/bench-ideal.yaml"});
  TwoRunsInARow("remote.yaml", fmt::format("127.0.0.1:{}", bench.port()), "bench",
                "p0 = 0.02 m (20 mm)", 0.005);
}

TEST(StartCheck, ContractModbusSecondRunRefusesThenRamps) {
  if (!PymodbusAvailable()) GTEST_SKIP() << kPymodbusMissing;
  auto server = ModbusServerProcess::Pymodbus({"--stiffness", "5.25"});
  TwoRunsInARow("modbus.yaml", server.address(), "modbus", "p0 = 0 m (0 mm)", 0.002);
}

}  // namespace
}  // namespace hybridtest::testing
