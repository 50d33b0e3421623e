// The `transfer: {type: ads}` section (transfer/ads/ads_config.h): defaults, overrides, and
// errors that name the key and the fix.
#include "hybridtest/transfer/ads/ads_config.h"

#include <gtest/gtest.h>

#include "hybridtest/common/error.h"

namespace hybridtest::transfer::ads {
namespace {

AdsOptions Parse(const std::string& text, std::optional<std::string> bench = std::nullopt) {
  const YamlInput in = YamlInput::FromText(text, "run.yaml");
  return ParseAdsOptions(in, in.root()["transfer"], "transfer", bench, 3.0);
}

std::string Error(const std::string& text) {
  try {
    Parse(text);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(AdsConfig, DefaultsAreTheProfileAndTwinCat3) {
  const AdsOptions o = Parse("transfer: {type: ads, host: 192.168.0.20}");
  EXPECT_EQ(o.endpoint.host, "192.168.0.20");
  EXPECT_EQ(o.endpoint.tcp_port, 48898);
  EXPECT_EQ(FormatAmsNetId(o.endpoint.target.net_id), "192.168.0.20.1.1");
  EXPECT_EQ(o.endpoint.target.port, 851);
  EXPECT_FALSE(o.endpoint.local_net_id.has_value());
  EXPECT_EQ(o.profile.actuators, 1);
  EXPECT_EQ(o.profile.symbols[kCommand], "GVL_Hybrid.fCommand");
  EXPECT_EQ(o.profile.units.length_name, "mm");
  EXPECT_DOUBLE_EQ(o.ack_timeout, 3.0);  // the slot's safety.timeout
  EXPECT_DOUBLE_EQ(*o.settle_tolerance, 0.05);
  EXPECT_DOUBLE_EQ(*o.following_error, 0.2);
}

TEST(AdsConfig, EveryNameUnitAndAddressIsConfigurable) {
  const AdsOptions o = Parse(R"(transfer:
  type: ads
  host: plc.lab
  ams_net_id: 5.80.201.232.1.1
  ams_port: 852
  local_ams_net_id: 10.0.0.5.1.1
  actuators: 3
  units: {length: m, force: kN}
  symbols: {command: MAIN.aTarget, fault: GVL_Safety.bAnyFault}
  following_error: [0.1, 0.2, 0.3]
)", "127.0.0.1:4000");
  EXPECT_EQ(o.endpoint.host, "127.0.0.1");  // --bench overrides host and port
  EXPECT_EQ(o.endpoint.tcp_port, 4000);
  EXPECT_EQ(FormatAmsNetId(o.endpoint.target.net_id), "5.80.201.232.1.1");
  EXPECT_EQ(o.endpoint.target.port, 852);
  EXPECT_EQ(FormatAmsNetId(*o.endpoint.local_net_id), "10.0.0.5.1.1");
  EXPECT_EQ(o.profile.actuators, 3);
  EXPECT_EQ(o.profile.units.force_name, "kN");
  EXPECT_EQ(o.profile.symbols[kCommand], "MAIN.aTarget");
  EXPECT_EQ(o.profile.symbols[kFault], "GVL_Safety.bAnyFault");
  EXPECT_EQ(o.profile.symbols[kAck], "GVL_Hybrid.nAckSeq");
  EXPECT_EQ(o.following_errors, (std::vector<double>{0.1, 0.2, 0.3}));
}

TEST(AdsConfig, ErrorsNameTheKeyAndTheFix) {
  EXPECT_NE(Error("transfer: {type: ads}").find("give `host:`"), std::string::npos);
  EXPECT_NE(Error("transfer: {type: ads, host: plc.lab}").find("give `ams_net_id:`"),
            std::string::npos);
  EXPECT_NE(Error("transfer: {type: ads, host: 10.0.0.1, ams_net_id: 1.2.3.4.5}")
                .find("transfer.ams_net_id"), std::string::npos);
  EXPECT_NE(Error("transfer: {type: ads, host: 10.0.0.1, symbols: {cmd: X}}")
                .find("unknown symbol role 'cmd': expected one of command, sequence"),
            std::string::npos);
  EXPECT_NE(Error("transfer: {type: ads, host: 10.0.0.1, actuators: 2, following_error: [1]}")
                .find("1 values for 2 actuators"), std::string::npos);
  EXPECT_NE(Error("transfer: {type: ads, host: 10.0.0.1, portt: 1}").find("portt"),
            std::string::npos);
}

TEST(AdsConfig, TheTransferRefusesBadTimesAndEmptyNames) {
  AdsOptions o;
  o.hold_timeout = 0.0;
  EXPECT_THROW(AdsTransfer{o}, ConfigError);
  AdsOptions p;
  p.profile.symbols[kHold] = "";
  EXPECT_THROW(AdsTransfer{p}, ConfigError);
}

}  // namespace
}  // namespace hybridtest::transfer::ads
