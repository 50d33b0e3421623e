// The readers of the in-process plants for several actuators: `rt_plant` with `actuators: n`
// (per-actuator lists, a specimen matrix in actuator coordinates) and `loopback` with one law
// per actuator; a list of the wrong length is refused naming the key.
#include "hybridtest/io/rt_plant_reader.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "hybridtest/common/error.h"
#include "hybridtest/common/yaml_input.h"

namespace hybridtest::io {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

std::unique_ptr<transfer::TransferSystem> Make(const std::string& text) {
  const YamlInput in = YamlInput::FromText(text, "t.yaml");
  const std::string kp = "transfer";
  const TransferReadContext context{in, in.root(), kp, std::nullopt, 5.0, nullptr, nullptr};
  return ReadTransfer(context).make();
}

std::string ErrorOf(const std::string& text) {
  try {
    Make(text);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(RtPlantReader, TwoActuatorsOnOneCoupledSpecimen) {
  const auto made = Make(
      "{type: rt_plant, plant: servo_hydraulic, actuators: 2, p0: [0.02, 0.03],\n"
      " delay: [0.0, 0.004], servo: [{gain: 1.0}, {a3: 4.0}],\n"
      " specimen: {mass: [10, 12], stiffness: [[5000, 1200], [1200, 3000]], zeta: [0.1, 0]}}");
  ASSERT_EQ(made->num_actuators(), 2);
  const auto& c = dynamic_cast<const transfer::RtPlant&>(*made).config();
  EXPECT_EQ(c.actuators[1].p0, 0.03);
  EXPECT_EQ(c.actuators[1].delay, 0.004);
  EXPECT_EQ(c.actuators[0].servo.gain, 1.0);
  EXPECT_EQ(c.actuators[1].servo.gain, 1.0261);  // the default
  EXPECT_EQ(c.actuators[1].servo.a3, 4.0);
  EXPECT_EQ(c.specimen.stiffness, (std::vector<double>{5000, 1200, 1200, 3000}));
  EXPECT_DOUBLE_EQ(c.specimen.damping[0], 2.0 * 0.1 * std::sqrt(5000.0 * 10.0));
  EXPECT_EQ(c.specimen.damping[1], 0.0);
  // A number applies to every actuator; a list of numbers is the diagonal.
  const auto diagonal = Make("{type: rt_plant, actuators: 2, delay: 0.002, "
                             "specimen: {stiffness: [5000, 3000]}}");
  const auto& d = dynamic_cast<const transfer::RtPlant&>(*diagonal).config();
  EXPECT_EQ(d.actuators[1].delay, 0.002);
  EXPECT_EQ(d.specimen.stiffness, (std::vector<double>{5000, 0, 0, 3000}));
}

TEST(RtPlantReader, AListOfTheWrongLengthIsRefusedNamingTheKey) {
  EXPECT_THAT(ErrorOf("{type: rt_plant, actuators: 2, p0: [0.0, 0.1, 0.2], "
                      "specimen: {stiffness: 1000}}"),
              AllOf(HasSubstr("transfer.p0"), HasSubstr("one per actuator")));
  EXPECT_THAT(ErrorOf("{type: rt_plant, actuators: 2, "
                      "specimen: {stiffness: [[1, 2, 3], [4, 5, 6]]}}"),
              AllOf(HasSubstr("transfer.specimen.stiffness"), HasSubstr("2 rows of 2")));
  EXPECT_THAT(ErrorOf("{type: rt_plant, actuators: 2, delay: [0, 5], "
                      "specimen: {stiffness: 1000}}"),
              AllOf(HasSubstr("transfer.delay"), HasSubstr("from 0 to 1")));
}

TEST(LoopbackReader, OneLawPerActuator) {
  const auto made = Make("{type: loopback, p0: [0.02, 0.03], law: [{type: linear, stiffness: "
                         "5000}, {type: linear, stiffness: 3000}]}");
  ASSERT_EQ(made->num_actuators(), 2);
  made->Activate();
  std::vector<transfer::Measurement> out(2);
  made->Execute(std::vector<double>{0.03, 0.01}, out);
  EXPECT_DOUBLE_EQ(out[0].force, 5000.0 * (0.03 - 0.02));
  EXPECT_DOUBLE_EQ(out[1].force, 3000.0 * (0.01 - 0.03));
  EXPECT_THAT(ErrorOf("{type: loopback, p0: [0.0], law: [{type: linear, stiffness: 1}, "
                      "{type: linear, stiffness: 2}]}"),
              AllOf(HasSubstr("transfer.p0"), HasSubstr("one per law")));
}

}  // namespace
}  // namespace hybridtest::io
