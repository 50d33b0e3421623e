// `model: {file: PATH}` in a run config: PATH is relative to the config; overrides apply by
// the file's parameter names; errors name the config's key path. And a model file's RHS
// allocates nothing after the first call (it runs in every stage of a real-time test).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <random>

#include "hybridtest/common/error.h"
#include "hybridtest/io/config.h"
#include "hybridtest/modelfile/model_file.h"
#include "hybridtest/multibody/kane.h"
#include "support/alloc_counter.h"
#include "support/multibody_helpers.h"

namespace hybridtest::modelfile {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

const std::string kConfigPath = HYBRIDTEST_SOURCE_DIR "/examples/01_rotor_model_file/test.yaml";

io::SimulationConfig Parse(const std::string& model_section) {
  return io::ParseSimulationConfig(YamlInput::FromText(
      model_section + "integrator: {tableau: heun, dt: 0.001}\nduration: 0.01\n", kConfigPath));
}

std::string ErrorOf(const std::string& model_section) {
  try {
    Parse(model_section);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ModelFileConfigTest, FileIsRelativeToTheConfigAndParametersOverride) {
  const io::SimulationConfig cfg =
      Parse("model:\n  file: ../models/rotor.yaml\n  parameters: {k_b: 5000, m_b: 2.5}\n");
  EXPECT_EQ(cfg.model.name, "rotor");
  EXPECT_EQ(cfg.model.model.num_coordinates(), 4);
  EXPECT_EQ(cfg.model.slot_stiffness[1], 5000.0);
  EXPECT_EQ(cfg.model.parameters.Get("m_b"), 2.5);
  EXPECT_EQ(cfg.x0.size(), 8);
}

TEST(ModelFileConfigTest, ErrorsNameTheConfigKey) {
  EXPECT_THAT(ErrorOf("model: {file: ../models/no_such.yaml}\n"),
              AllOf(HasSubstr("test.yaml:1: model.file"), HasSubstr("relative to the run config")));
  EXPECT_THAT(ErrorOf("model: {file: ../models/rotor.yaml, parameters: {k_bb: 1}}\n"),
              AllOf(HasSubstr("model.parameters.k_bb"), HasSubstr("k_b")));
  EXPECT_THAT(ErrorOf("model: {file: ../models/rotor.yaml, blades: 4}\n"), HasSubstr("blades"));
}

TEST(ModelFileConfigTest, ModelFileRightHandSideDoesNotAllocate) {
  if (!test_support::kCanCountAllocations) GTEST_SKIP() << "malloc cannot be counted here";
  std::mt19937 rng(4);
  // The last three use atan2, if, tables and velocity() in loads; turbine_functions and the
  // turbine example have extra states.
  for (const std::string name : {"rotor", "spinning_top", "wind_turbine", "cart_pendulum",
                                 "../../tests/modelfile/data/turbine_functions",
                                 "../../tests/modelfile/data/top_drag",
                                 "../05_turbine_lab/turbine.model"}) {
    const ModelFile f = LoadModelFile(HYBRIDTEST_SOURCE_DIR "/examples/models/" + name + ".yaml");
    const models::BuiltModel built = BuildModelFile(f, f.parameters);
    const multibody::Model& model = built.model;
    multibody::Data<double> data(model);
    Eigen::VectorXd x = Eigen::VectorXd::Constant(model.num_states(), 0.3);  // z: 0.3
    x.head(2 * model.num_coordinates()) = test_support::RandomState(
        rng, Eigen::VectorXd::Constant(model.num_coordinates(), 0.2), 1.0);
    const Eigen::VectorXd r = test_support::RandomForces(rng, model.num_slots(), 10.0);
    Eigen::VectorXd xdot(model.num_states()), d(model.num_slots());
    multibody::CalcStateDerivative<double>(model, data, 0.0, x, r, xdot);
    const long allocations = test_support::CountAllocations([&] {
      for (int i = 0; i < 5; ++i) {
        multibody::CalcStateDerivative<double>(model, data, 0.01 * i, x, r, xdot);
        multibody::CalcSlotDisplacements<double>(model, data, 0.01 * i,
                                                 x.head(model.num_coordinates()), d);
      }
    });
    EXPECT_EQ(allocations, 0) << name;
    EXPECT_TRUE(xdot.allFinite()) << name;
  }
}

}  // namespace
}  // namespace hybridtest::modelfile
