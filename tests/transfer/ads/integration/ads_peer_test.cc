// An independent ADS client against our TwinCAT PLC emulator: the npm package ads-client
// (2.x; tests/transfer/ads/peer/, installed there by peer/install.sh from its package.json)
// connects to `hybridtest bench --protocol ads`, reads every symbol of the profile by name
// with its IEC type and size, takes handles, enables the drive and drives one command to its
// acknowledgement (peer/peer.js). One actuator and two. Skipped, with a message, only when
// node or npm is not installed (scripts/install-deps.sh installs both).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "integration/bench_process.h"
#include "integration/resume_support.h"

namespace hybridtest::testing {
namespace {

const std::string kPeer = kSource + "/tests/transfer/ads/peer/";

bool NodeAndNpmInstalled() {
  const fs::path log = fs::temp_directory_path() / fmt::format("hybridtest_ads_which_{}", ::getpid());
  Child which({"/bin/sh", "-c", "command -v node && command -v npm"}, log);
  const int status = which.WaitExit(30.0);
  fs::remove(log);
  return status == 0;
}

// Installs ads-client (once) and runs the peer against a PLC of `bench_file`.
std::pair<int, std::string> RunPeer(const std::string& bench_file, int actuators) {
  const fs::path dir = ResumeTestDir(fmt::format("ads-peer-{}", actuators));
  Child install({"/bin/sh", kPeer + "install.sh"}, dir / "install.log");
  const int installed = install.WaitExit(600.0);
  if (installed != 0) return {installed, "npm install failed: " + install.output()};
  BenchProcess plc({"--protocol", "ads", "--config", bench_file});
  Child peer({"/bin/sh", "-c", fmt::format("cd '{}' && exec node peer.js 127.0.0.1 {} {}", kPeer,
                                           plc.port(), actuators)},
             dir / "peer.log");
  const int status = peer.WaitExit(120.0);
  std::string output = peer.output();
  fs::remove_all(dir);
  return {status, output};
}

TEST(AdsPeer, AdsClientReadsEverySymbolAndDrivesOneCommandToItsAck) {
  if (!NodeAndNpmInstalled()) {
    GTEST_SKIP() << "node and npm are not installed: run scripts/install-deps.sh (Debian: "
                    "apt-get install nodejs npm) to check the ADS emulator against ads-client";
  }
  const auto [status, output] = RunPeer(kSource + "/examples/rotor/bench-ideal.yaml", 1);
  EXPECT_EQ(status, 0) << output;
  EXPECT_NE(output.find("ads-client peer: OK"), std::string::npos) << output;
  // Eleven: the GVL of docs/ads.md, nHeartbeat included (the watchdog's counter).
  EXPECT_NE(output.find("11 symbols checked, command [20.25] acknowledged"), std::string::npos)
      << output;
  // The ideal bench: zero force at 20 mm, 7200 N/m: 0.25 mm gives 1.8 N.
  EXPECT_NE(output.find("force [1.8"), std::string::npos) << output;
  std::cout << output;
}

TEST(AdsPeer, AdsClientDrivesBothActuatorsOfATwoActuatorPlc) {
  if (!NodeAndNpmInstalled()) GTEST_SKIP() << "node and npm are not installed";
  const auto [status, output] =
      RunPeer(kSource + "/examples/06_blade_two_actuators/bench-2act.yaml", 2);
  EXPECT_EQ(status, 0) << output;
  EXPECT_NE(output.find("command [20.25,30.5] acknowledged"), std::string::npos) << output;
}

}  // namespace
}  // namespace hybridtest::testing
