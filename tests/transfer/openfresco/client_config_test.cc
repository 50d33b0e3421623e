// The run-config form of the OpenFresco client: `transfer: {type: openfresco, ...}`.
#include "hybridtest/transfer/openfresco/client_config.h"

#include <gtest/gtest.h>

#include <string>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/openfresco/client.h"

namespace hybridtest::transfer::openfresco {
namespace {

std::unique_ptr<TransferSystem> Make(const std::string& yaml,
                                     const std::optional<std::string>& bench = std::nullopt) {
  const YamlInput in = YamlInput::FromText(yaml, "run.yaml");
  return MakeClientTransfer(in, in.root()["transfer"], "substructures.r1.transfer", bench, 3.0);
}

std::string ErrorOf(const std::string& yaml) {
  try {
    Make(yaml);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "accepted";
}

TEST(OpenFrescoClientConfig, ReadsHostPortUnitsAndTimeout) {
  auto t = Make("transfer: {type: openfresco, host: 127.0.0.1, port: 8090, "
                "units: {length: m, force: kN}, timeout: 7}");
  const auto* client = dynamic_cast<const Client*>(t.get());
  ASSERT_NE(client, nullptr);
  EXPECT_EQ(client->options().host, "127.0.0.1");
  EXPECT_EQ(client->options().port, 8090);
  EXPECT_EQ(client->options().reply_timeout, 7.0);
  EXPECT_EQ(client->bench_units().metres_per_length_unit, 1.0);
  EXPECT_EQ(client->bench_units().newtons_per_force_unit, 1e3);
  EXPECT_FALSE(client->is_connected());  // connects in Activate()
}

TEST(OpenFrescoClientConfig, BenchAddressOverridesAndDefaultsApply) {
  auto t = Make("transfer: {type: openfresco}", std::string("[::1]:9000"));
  const auto* client = dynamic_cast<const Client*>(t.get());
  ASSERT_NE(client, nullptr);
  EXPECT_EQ(client->options().host, "::1");
  EXPECT_EQ(client->options().port, 9000);
  EXPECT_EQ(client->options().reply_timeout, 3.0);  // the safety section's timeout
  EXPECT_EQ(client->bench_units().length_name, "mm");
}

TEST(OpenFrescoClientConfig, ErrorsNameTheKey) {
  EXPECT_NE(ErrorOf("transfer: {type: openfresco}").find("--bench HOST:PORT"), std::string::npos);
  EXPECT_NE(ErrorOf("transfer: {type: openfresco, host: h, port: 70000}").find("port"),
            std::string::npos);
  EXPECT_NE(ErrorOf("transfer: {type: openfresco, host: h, port: 1, adress: x}").find("adress"),
            std::string::npos);
  EXPECT_NE(ErrorOf("transfer: {type: openfresco, host: h, port: 1, timeout: -1}")
                .find("substructures.r1.transfer.timeout"),
            std::string::npos);
}

}  // namespace
}  // namespace hybridtest::transfer::openfresco
