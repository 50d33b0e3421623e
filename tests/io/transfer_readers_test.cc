// The transfer types a config can name: one registry, whose list every message quotes, per-type
// keys, and a program's own type read from the same YAML.
#include "hybridtest/io/transfer_readers.h"

#include <gtest/gtest.h>

#include "hybridtest/io/config.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/transfer/numerical_loopback.h"
#include "hybridtest/constitutive/linear_spring.h"

namespace hybridtest::io {
namespace {

std::string Config(const std::string& transfer) {
  return "model: {name: rotor, blades: 3}\n"
         "integrator: {tableau: heun, dt: 0.001}\n"
         "duration: 0.01\n"
         "substructures:\n"
         "  r1:\n"
         "    type: physical\n"
         "    transfer: " + transfer + "\n"
         "    safety: defaults\n";
}

std::string ErrorOf(const std::string& transfer) {
  try {
    CompileRunSpec(ParseSimulationConfig(YamlInput::FromText(Config(transfer), "t.yaml")));
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(TransferReaders, TheBuiltInTypesAndOneList) {
  const auto types = TransferTypes();
  for (const char* t : {"emulated", "fmu", "loopback", "modbus", "openfresco", "remote"}) {
    EXPECT_NE(std::find(types.begin(), types.end(), t), types.end()) << t;
  }
  const std::string unknown = ErrorOf("{type: hydraulic}");
  EXPECT_NE(unknown.find("t.yaml:7"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("'hydraulic'"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("emulated, fmu, loopback, modbus, openfresco, remote"), std::string::npos)
      << unknown;
}

TEST(TransferReaders, EachTypeChecksItsOwnKeys) {
  // `address` belongs to remote; an emulated bench with one is a slip, named.
  const std::string e = ErrorOf("{type: loopback, law: {type: linear, stiffness: 7200}, address: x}");
  EXPECT_NE(e.find("address"), std::string::npos) << e;
  EXPECT_EQ(ErrorOf("{type: loopback, law: {type: linear, stiffness: 7200}, p0: 0.0}"), "");
}

TEST(TransferReaders, AProgramRegistersItsOwnType) {
  int made = 0;
  RegisterTransferReader("my-rig", [&made](const TransferReadContext& c) {
    c.in.CheckKeys(c.node, c.kp, {"type", "stiffness"});
    const double k = c.in.PositiveNumber(c.node["stiffness"], c.kp + ".stiffness", "N/m");
    return substructures::TransferSpec{"my-rig", [k, &made] {
                                         ++made;
                                         return std::make_unique<transfer::NumericalLoopback>(
                                             std::make_unique<constitutive::LinearSpring>(k), 0.0);
                                       }};
  });
  const RunSpec spec = CompileRunSpec(ParseSimulationConfig(
      YamlInput::FromText(Config("{type: my-rig, stiffness: 7200}"), "t.yaml")));
  ASSERT_TRUE(spec.substructures[0].physical.has_value());
  EXPECT_EQ(spec.substructures[0].physical->transfer.type, "my-rig");
  EXPECT_EQ(made, 0);  // read once, built on demand
  const auto built = spec.substructures[0].Build();
  EXPECT_EQ(made, 1);
  EXPECT_TRUE(built->is_physical());
  const auto types = TransferTypes();
  EXPECT_NE(std::find(types.begin(), types.end(), "my-rig"), types.end());
}

}  // namespace
}  // namespace hybridtest::io
