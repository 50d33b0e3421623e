// The run config's large-displacement `setup:` and `safety.slots:`: what a good one compiles
// to, and a ConfigError naming the key path (and the fix) for each kind of bad one.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "hybridtest/common/error.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/substructures/rod_setup.h"
#include "support/temp_dir.h"

namespace hybridtest::substructures {
namespace {

namespace fs = std::filesystem;

const std::string kExample =
    std::string(HYBRIDTEST_SOURCE_DIR) + "/examples/06_blade_two_actuators/";

std::string ExampleText() {
  std::ifstream in(kExample + "large-displacement.yaml");
  std::string text, line;
  while (std::getline(in, line)) text += line + "\n";
  return text;
}

// The example with `from` replaced by `to` (which must occur), loaded from a temporary folder.
io::RunSpec LoadEdited(const std::string& from, const std::string& to) {
  std::string text = ExampleText();
  const auto at = text.find(from);
  if (at == std::string::npos) throw std::runtime_error("test: no '" + from + "' in the example");
  text.replace(at, from.size(), to);
  const fs::path dir = test_support::FreshTempDir("hybridtest-rod-config");
  fs::create_directories(dir);
  for (const char* f : {"blade_tip.yaml", "bench-2act.yaml"}) {
    fs::copy_file(kExample + f, dir / f, fs::copy_options::overwrite_existing);
  }
  std::ofstream(dir / "edited.yaml") << text;
  return io::LoadRunSpec((dir / "edited.yaml").string());
}

std::string ErrorOf(const std::string& from, const std::string& to) {
  try {
    LoadEdited(from, to);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(RodConfig, TheExampleCompilesToARodSetupWithSlotLimits) {
  const io::RunSpec spec = io::LoadRunSpec(kExample + "large-displacement.yaml");
  ASSERT_EQ(spec.substructures.size(), 1u);
  const auto& physical = *spec.substructures[0].physical;
  ASSERT_TRUE(physical.actuator_setup);
  EXPECT_FALSE(physical.linear);
  EXPECT_EQ(physical.actuator_setup->kind(), "large_displacement");
  const auto& rods = static_cast<const RodSetup&>(*physical.actuator_setup);
  EXPECT_NEAR(rods.rest_lengths()(0), 0.25, 1e-15);
  EXPECT_NEAR(rods.rest_lengths()(1), 0.25, 1e-15);
  Eigen::Matrix2d t0;
  t0 << 1.0, 0.0, 0.6, 0.8;
  EXPECT_LT((rods.linearisation() - t0).cwiseAbs().maxCoeff(), 1e-15);
  ASSERT_TRUE(physical.slot_limits);
  EXPECT_EQ(physical.slot_limits->max_displacement(1), 0.08);
  EXPECT_EQ(physical.slot_limits->max_force(0), 600.0);
  EXPECT_EQ(spec.substructures[0].num_actuators(), 2);
  ASSERT_EQ(physical.actuator_limits.size(), 2u);
  EXPECT_EQ(physical.actuator_limits[1].max_increment, 0.005);
  // A scalar slot limit applies to every slot.
  const io::RunSpec scalar = LoadEdited("max_force: [600, 400]", "max_force: 500");
  EXPECT_EQ(scalar.substructures[0].physical->slot_limits->max_force(1), 500.0);
}

struct BadCase {
  const char* from;
  const char* to;
  const char* expected;  // in the message
};

TEST(RodConfig, BadSetupsNameTheirKey) {
  const BadCase cases[] = {
      {"geometry: large_displacement", "geometry: large", "blade1.setup.geometry"},
      {"directions: [[1, 0], [0, 1]]", "directions: [[1, 0]]", "blade1.setup.directions"},
      {"directions: [[1, 0], [0, 1]]", "directions: [[1, 0], [0, 0]]", "directions[1]"},
      {"directions: [[1, 0], [0, 1]]", "directions: [[1, 0, 0], [0, 1]]",
       "blade1.setup.directions[1]"},
      {"{base: [-0.15, -0.20], attach: [0.0, 0.0]}", "{base: [-0.15, -0.20, 0], attach: [0, 0]}",
       "blade1.setup.actuators[1].base"},
      {"{base: [-0.15, -0.20], attach: [0.0, 0.0]}", "{base: [0, 0], attach: [0.0, 0.0]}",
       "actuators[1]: base"},
      {"{base: [-0.15, -0.20], attach: [0.0, 0.0]}", "{base: [-0.5, 0], attach: [0.0, 0.0]}",
       "rank 1"},
      {"{base: [-0.15, -0.20], attach: [0.0, 0.0]}", "{base: [-0.15, -0.20], tip: [0.0, 0.0]}",
       "tip"},
      {"p0: [0.02, 0.03]", "p0: [0.02]", "blade1.setup.p0"},
      {"      p0: [0.02, 0.03]                  # [m] actuator positions at zero specimen force\n",
       "", "blade1.setup.p0"},
      {"directions:", "transform: [[1, 0], [0, 1]]\n      directions:", "transform"},
      {"max_force: [600, 400]", "max_force: [600, 400, 300]", "blade1.safety.slots.max_force"},
      {"max_force: [600, 400]", "max_force: [600, -400]", "blade1.safety.slots.max_force"},
      {"max_force: [600, 400]", "max_forces: [600, 400]", "max_forces"},
      // A flap rod of 0.1 m with the tip allowed 80 mm towards its base: it turns edgewise.
      {"{base: [-0.25, 0.0], attach: [0.0, 0.0]}", "{base: [-0.1, 0.0], attach: [0.0, 0.0]}",
       "nearly parallel"},
  };
  for (const auto& c : cases) {
    const std::string message = ErrorOf(c.from, c.to);
    EXPECT_NE(message.find(c.expected), std::string::npos)
        << "replacing '" << c.from << "' by '" << c.to << "': " << message;
  }
}

TEST(RodConfig, ARotationalSlotIsReadFromItsDirectionEntry) {
  // The edge slot read as a turn about a point 0.5 m behind the tip: at d = 0 it moves the
  // tip along y by 0.5 m per rad, so J(0)'s second column is 0.5 times the linear one.
  const io::RunSpec spec = LoadEdited("directions: [[1, 0], [0, 1]]",
                                      "directions: [[1, 0], {rotation_about: [-0.5, 0]}]");
  const auto& rods =
      static_cast<const RodSetup&>(*spec.substructures[0].physical->actuator_setup);
  EXPECT_EQ(rods.geometry().rotation_slot, 1);
  EXPECT_NEAR(rods.linearisation()(1, 1), 0.8 * 0.5, 1e-15);
  EXPECT_NEAR(rods.linearisation()(0, 1), 0.0, 1e-15);
  EXPECT_NE(rods.Describe().find("1 rotational"), std::string::npos) << rods.Describe();
  const BadCase cases[] = {
      {"directions: [[1, 0], [0, 1]]",
       "directions: [{rotation_about: [0, 0]}, {rotation_about: [-0.5, 0]}]",
       "a second rotational slot"},
      {"directions: [[1, 0], [0, 1]]", "directions: [[1, 0], {rotation_about: [-0.5, 0], axis: [0, 0, 1]}]",
       "directions[1].axis"},
      {"directions: [[1, 0], [0, 1]]", "directions: [[1, 0], {about: [-0.5, 0]}]", "about"},
      {"directions: [[1, 0], [0, 1]]", "directions: [[1, 0], {rotation_about: [-0.5, 0, 0]}]",
       "directions[1].rotation_about"},
  };
  for (const auto& c : cases) {
    const std::string message = ErrorOf(c.from, c.to);
    EXPECT_NE(message.find(c.expected), std::string::npos) << "'" << c.to << "': " << message;
  }
}

TEST(RodConfig, MissingSetupOrSafetyIsNamed) {
  const std::string text = ExampleText();
  const auto safety = text.find("    safety:"), output = text.find("output:");
  const auto setup = text.find("    setup:");
  ASSERT_NE(safety, std::string::npos);
  const fs::path dir = test_support::FreshTempDir("hybridtest-rod-config-missing");
  fs::create_directories(dir);
  for (const char* f : {"blade_tip.yaml", "bench-2act.yaml"}) {
    fs::copy_file(kExample + f, dir / f, fs::copy_options::overwrite_existing);
  }
  auto error_of = [&](const std::string& config) -> std::string {
    std::ofstream(dir / "missing.yaml") << config;
    try {
      io::LoadRunSpec((dir / "missing.yaml").string());
    } catch (const ConfigError& e) {
      return e.what();
    }
    return "(no error)";
  };
  const std::string no_safety = text.substr(0, safety) + text.substr(output);
  const std::string m1 = error_of(no_safety);
  EXPECT_NE(m1.find("blade1.safety"), std::string::npos) << m1;
  EXPECT_NE(m1.find("missing"), std::string::npos) << m1;
  const std::string no_setup = text.substr(0, setup) + text.substr(safety);
  const std::string m2 = error_of(no_setup);
  EXPECT_NE(m2.find("blade1.setup"), std::string::npos) << m2;
  EXPECT_NE(m2.find("large_displacement"), std::string::npos) << m2;
  fs::remove_all(dir);
}

TEST(RodConfig, ARodSetupThatTurnsSingularWithinTheStrokeIsRefused) {
  std::string text = ExampleText();
  auto edit = [&](const std::string& from, const std::string& to) {
    text.replace(text.find(from), from.size(), to);
  };
  // Rods of 0.1 m at right angles; the tip reaches (−0.05, −0.05), on the line through both
  // bases, within the slot limits: the rods are collinear there.
  edit("{base: [-0.25, 0.0], attach: [0.0, 0.0]}", "{base: [-0.1, 0.0], attach: [0.0, 0.0]}");
  edit("{base: [-0.15, -0.20], attach: [0.0, 0.0]}", "{base: [0.0, -0.1], attach: [0.0, 0.0]}");
  edit("max_displacement: [0.08, 0.08]", "max_displacement: [0.05, 0.05]");
  const fs::path dir = test_support::FreshTempDir("hybridtest-rod-config");
  fs::create_directories(dir);
  for (const char* f : {"blade_tip.yaml", "bench-2act.yaml"}) {
    fs::copy_file(kExample + f, dir / f, fs::copy_options::overwrite_existing);
  }
  std::ofstream(dir / "singular.yaml") << text;
  try {
    io::LoadRunSpec((dir / "singular.yaml").string());
    FAIL() << "accepted";
  } catch (const ConfigError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("blade1.setup"), std::string::npos) << m;
    EXPECT_NE(m.find("nearly parallel"), std::string::npos) << m;
    EXPECT_NE(m.find("safety.slots.max_displacement"), std::string::npos) << m;
  }
  // Slot limits that keep the tip away from there: accepted.
  std::string near = text;
  near.replace(near.find("max_displacement: [0.05, 0.05]"), 30, "max_displacement: [0.02, 0.02]");
  std::ofstream(dir / "limited.yaml") << near;
  EXPECT_NO_THROW(io::LoadRunSpec((dir / "limited.yaml").string()));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hybridtest::substructures
