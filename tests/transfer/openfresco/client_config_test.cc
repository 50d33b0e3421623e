// The run-config form of the OpenFresco client: `transfer: {type: openfresco, ...}`.
#include "hybridtest/transfer/openfresco/client_config.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/auth.h"
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

// Issue 15: an inline token was copied into the sidecars, report.html and the HDF5 export.
TEST(OpenFrescoClientConfig, InlineTokenIsRefusedNamingTheKeyAndTheFix) {
  const std::string what =
      ErrorOf("transfer: {type: openfresco, host: h, port: 1, token: s3cret-s3cret-s3cret}");
  EXPECT_NE(what.find("substructures.r1.transfer.token"), std::string::npos) << what;
  EXPECT_NE(what.find("token_file: PATH"), std::string::npos) << what;
  EXPECT_NE(what.find(kTokenEnvironmentVariable), std::string::npos) << what;
  EXPECT_EQ(what.find("s3cret"), std::string::npos) << "the error repeats the secret: " << what;
}

TEST(OpenFrescoClientConfig, TokenComesFromTheFileOrTheEnvironment) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("hybridtest_of_token_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto file = dir / "bench.token";
  std::ofstream(file) << "from-the-file-0123456\n";
  {
    auto t = Make("transfer: {type: openfresco, host: h, port: 1, token_file: " +
                  file.string() + "}");
    EXPECT_EQ(dynamic_cast<const Client&>(*t).options().token, "from-the-file-0123456");
  }
  // Relative to the run config.
  {
    const YamlInput in = YamlInput::FromText(
        "transfer: {type: openfresco, host: h, port: 1, token_file: bench.token}",
        (dir / "run.yaml").string());
    auto t = MakeClientTransfer(in, in.root()["transfer"], "substructures.r1.transfer",
                                std::nullopt, 3.0);
    EXPECT_EQ(dynamic_cast<const Client&>(*t).options().token, "from-the-file-0123456");
  }
  EXPECT_NE(ErrorOf("transfer: {type: openfresco, host: h, port: 1, token_file: " +
                    (dir / "missing").string() + "}")
                .find("substructures.r1.transfer.token_file"),
            std::string::npos);
  // Without token_file: the environment.
  ::setenv(kTokenEnvironmentVariable, "from-the-environment", 1);
  {
    auto t = Make("transfer: {type: openfresco, host: h, port: 1}");
    EXPECT_EQ(dynamic_cast<const Client&>(*t).options().token, "from-the-environment");
  }
  ::unsetenv(kTokenEnvironmentVariable);
  {
    auto t = Make("transfer: {type: openfresco, host: h, port: 1}");
    EXPECT_EQ(dynamic_cast<const Client&>(*t).options().token, "");
  }
  std::filesystem::remove_all(dir);
}

// `dofs:` against the substructure the transfer belongs to (found from the document's root).
std::string DofsErrorOf(const std::string& substructure) {
  const YamlInput in = YamlInput::FromText("substructures:\n  blade1: " + substructure, "run.yaml");
  try {
    auto t = MakeClientTransfer(in, in.root()["substructures"]["blade1"]["transfer"],
                                "substructures.blade1.transfer", std::nullopt, 3.0);
    return "accepted, n = " + std::to_string(t->num_actuators());
  } catch (const ConfigError& e) {
    return e.what();
  }
}

TEST(OpenFrescoClientConfig, DofsMatchTheSubstructuresActuators) {
  const std::string two =
      "{type: physical, slots: [r_flap, r_edge], setup: {p0: [0, 0], transform: [[1, 0], [0, "
      "1]]}, transfer: {type: openfresco, host: h, port: 1";
  EXPECT_EQ(DofsErrorOf(two + ", dofs: 2}}"), "accepted, n = 2");
  EXPECT_EQ(DofsErrorOf("{type: physical, transfer: {type: openfresco, host: h, port: 1}}"),
            "accepted, n = 1");
  // Two slots, the default dofs (1): the fix is `dofs: 2`.
  std::string what = DofsErrorOf(two + "}}");
  EXPECT_NE(what.find("run.yaml:2"), std::string::npos) << what;
  EXPECT_NE(what.find("dofs = 1 (the default"), std::string::npos) << what;
  EXPECT_NE(what.find("substructures.blade1 drives 2 actuators"), std::string::npos) << what;
  EXPECT_NE(what.find("give `dofs: 2`"), std::string::npos) << what;
  // dofs: 3 on two slots; dofs: 2 on one slot (the fix names the identity setup).
  what = DofsErrorOf(two + ", dofs: 3}}");
  EXPECT_NE(what.find("substructures.blade1.transfer.dofs"), std::string::npos) << what;
  EXPECT_NE(what.find("dofs = 3"), std::string::npos) << what;
  what = DofsErrorOf("{type: physical, transfer: {type: openfresco, host: h, port: 1, dofs: 2}}");
  EXPECT_NE(what.find("serves one slot"), std::string::npos) << what;
  EXPECT_NE(what.find("transform: [[1, 0], [0, 1]]"), std::string::npos) << what;
  EXPECT_NE(what.find("p0: [0, 0]"), std::string::npos) << what;
  EXPECT_NE(DofsErrorOf(two + ", dofs: 0}}").find("1 to 1024"), std::string::npos);
  EXPECT_NE(DofsErrorOf(two + ", dofs: two}}").find("substructures.blade1.transfer.dofs"),
            std::string::npos);
}

}  // namespace
}  // namespace hybridtest::transfer::openfresco
