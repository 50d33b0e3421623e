// Model-file errors name file:line, the key path, the token and the fix; the double pendulum
// and spinning top files equal their C++ models.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <random>

#include "hybridtest/common/error.h"
#include "hybridtest/modelfile/model_file.h"
#include "support/model_file_error.h"
#include "support/multibody_helpers.h"

namespace hybridtest::modelfile {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

constexpr char kBase[] =
    "name: p\n"                                             // 1
    "parameters:\n"                                         // 2
    "  l: {value: 1.0, unit: m}\n"                          // 3
    "coordinates:\n"                                        // 4
    "  - {name: th, unit: rad}\n"                           // 5
    "frames:\n"                                             // 6
    "  - {name: A, parent: N, axis: z, angle: th}\n"        // 7
    "points:\n"                                             // 8
    "  - {name: P, from: O, frame: A, position: [l, 0, 0]}\n"  // 9
    "particles:\n"                                          // 10
    "  - {name: bob, point: P, mass: 2}\n";                 // 11

std::string ErrorOf(const std::string& text) { return ::test_support::ModelFileError(text); }

TEST(ModelFileErrorsTest, AValidFileBuilds) { EXPECT_EQ(ErrorOf(kBase), "no error"); }

TEST(ModelFileErrorsTest, ErrorsNamePlaceTokenAndFix) {
  std::string s = kBase;
  EXPECT_THAT(ErrorOf(s + "forces:\n  - {name: f, point: Q, value: [0, 0, 0]}\n"),
              AllOf(HasSubstr("m.yaml:13: forces[0].point"), HasSubstr("unknown point"),
                    HasSubstr("did you mean")));
  EXPECT_THAT(ErrorOf(s + "torques:\n  - {name: f, frame: A, value: [0, 0, sin(r9)]}\n"),
              AllOf(HasSubstr("m.yaml:13"), HasSubstr("torques[0].value[2]"), HasSubstr("'r9'")));
  EXPECT_THAT(ErrorOf(s + "slots:\n  - {name: r1, unit: N·m, displacement: th, stiffness: 1}\n"
                          "torques:\n  - {name: f, frame: A, value: [0, 0, sin(0.001 * r1)]}\n"),
              HasSubstr("not linear in the slots"));
  EXPECT_THAT(ErrorOf(s + "slots:\n  - {name: r1, unit: kN, displacement: th}\n"),
              AllOf(HasSubstr("slots[0].unit"), HasSubstr("N·m")));
  EXPECT_THAT(ErrorOf(s + "bodies:\n  - {name: b, frame: A, mass_center: P, mass: th, inertia: [1, 1, 1]}\n"),
              AllOf(HasSubstr("bodies[0].mass"), HasSubstr("a constant")));
  EXPECT_THAT(ErrorOf(s + "frames2: 1\n"), HasSubstr("frames2"));
  std::string bad_dcm = s;
  bad_dcm.replace(bad_dcm.find("axis: z, angle: th"), 18, "dcm: [[1, 0, 0], [0, 2, 0], [0, 0, 1]]");
  EXPECT_THAT(ErrorOf(bad_dcm), AllOf(HasSubstr("m.yaml:7: frames[0].dcm"), HasSubstr("not a rotation")));
  std::string speed_in_position = s;
  speed_in_position.replace(speed_in_position.find("[l, 0, 0]"), 9, "[l, u1, 0]");
  EXPECT_THAT(ErrorOf(speed_in_position), AllOf(HasSubstr("points[0].position[1]"), HasSubstr("speed")));
}

double Relative(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(1.0, b.cwiseAbs().maxCoeff());
}

TEST(ModelFileErrorsTest, PendulumAndTopFilesEqualTheirCppModels) {
  std::mt19937 rng(2);
  for (const std::string name : {"double_pendulum", "spinning_top"}) {
    const ModelFile f = LoadModelFile(HYBRIDTEST_SOURCE_DIR "/examples/models/" + name + ".yaml");
    const models::BuiltModel file = BuildModelFile(f, f.parameters);
    const models::BuiltModel cpp = test_support::DefaultModel(name);
    for (int trial = 0; trial < 10; ++trial) {
      const Eigen::VectorXd x = test_support::RandomState(rng, test_support::CoordinateScales(cpp), 3.0);
      EXPECT_LT(Relative(test_support::StateDerivative(file.model, 0.1, x, {}),
                         test_support::StateDerivative(cpp.model, 0.1, x, {})), 1e-13) << name;
    }
  }
}

}  // namespace
}  // namespace hybridtest::modelfile
