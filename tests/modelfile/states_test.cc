// Extra first-order states in model files (`states:`): they join the state after q and u,
// loads read them, their rates and initial values are read as written, and every misuse is
// refused with file:line and the fix.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "hybridtest/common/error.h"
#include "hybridtest/modelfile/model_file.h"
#include "hybridtest/multibody/kane.h"

namespace hybridtest::modelfile {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

// A pendulum (th) with a slot at the bob; `states` replaces line 10 on, `loads` follows.
std::string Pendulum(const std::string& states, const std::string& loads = "") {
  return "name: p\n"                                                     // 1
         "parameters:\n"                                                 // 2
         "  L: {value: 500, unit: mm}\n"                                 // 3
         "  tau: {value: 200, unit: ms}\n"                               // 4
         "coordinates:\n"                                                // 5
         "  - {name: th, unit: rad}\n"                                   // 6
         "frames:\n"                                                     // 7
         "  - {name: A, parent: N, axis: z, angle: th}\n"                // 8
         "points:\n"                                                     // 9
         "  - {name: P, from: O, frame: A, position: [L, 0, 0]}\n"       // 10
         "particles:\n"                                                  // 11
         "  - {name: bob, point: P, mass: 2}\n"                          // 12
         "slots:\n"                                                      // 13
         "  - {name: r1, unit: N·m, displacement: th, stiffness: 10}\n"  // 14
         + states + loads;
}

models::BuiltModel Build(const std::string& text) {
  const ModelFile f = ParseModelFile(YamlInput::FromText(text, "m.yaml"));
  return BuildModelFile(f, f.parameters);
}

std::string ErrorOf(const std::string& text) {
  try {
    Build(text);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ModelFileStates, JoinTheStateAfterQAndUAndFeedTheLoads) {
  // ż1 = tip speed − z1/τ (a filter of velocity()), ż2 = z1 (its integral); the torque
  // −r1 − 3 z1 − 0.5 z2 on A.
  const models::BuiltModel b = Build(Pendulum(
      "states:\n"
      "  z1: {rate: \"(velocity(P, A).y - z1) / tau\", initial: 0.25, unit: m/s, description: filtered tip speed}\n"
      "  z2: {rate: z1, initial: 300 mm, unit: m}\n",
      "torques:\n  - {name: t, frame: A, value: [0, 0, \"-r1 - 3 * z1 - 0.5 * z2\"]}\n"));
  const multibody::Model& m = b.model;
  ASSERT_EQ(m.num_extra_states(), 2);
  ASSERT_EQ(m.num_states(), 4);
  EXPECT_EQ(m.extra_states()[0].info.name, "z1");
  EXPECT_EQ(m.extra_states()[0].info.unit, "m/s");
  EXPECT_EQ(m.extra_states()[0].info.description, "filtered tip speed");
  EXPECT_DOUBLE_EQ(m.extra_states()[0].initial, 0.25);
  EXPECT_DOUBLE_EQ(m.extra_states()[1].initial, 0.3);  // units are converted
  EXPECT_EQ(m.extra_states()[1].info.unit, "m");

  const double th = 0.3, w = -1.2, z1 = 0.4, z2 = -0.7, r = 5.0;
  Eigen::VectorXd x(4), xdot(4);
  x << th, w, z1, z2;
  multibody::Data<double> data(m);
  multibody::CalcStateDerivative<double>(m, data, 0.0, x, Eigen::VectorXd::Constant(1, r), xdot);
  const double I = 2.0 * 0.5 * 0.5;
  EXPECT_NEAR(xdot(0), w, 1e-15);
  EXPECT_NEAR(xdot(1), (-r - 3 * z1 - 0.5 * z2) / I, 1e-13);
  EXPECT_NEAR(xdot(2), (0.5 * w - z1) / 0.2, 1e-13);
  EXPECT_NEAR(xdot(3), z1, 1e-15);
}

TEST(ModelFileStates, MisuseIsRefusedWithThePlaceAndTheFix) {
  EXPECT_THAT(ErrorOf(Pendulum("states:\n  z: {initial: 0}\n")),
              AllOf(HasSubstr("m.yaml:16: states.z.rate: missing"), HasSubstr("ż")));
  EXPECT_THAT(ErrorOf(Pendulum("states:\n  z: {rate: 0.5 * r1 - z}\n")),
              AllOf(HasSubstr("m.yaml:16: states.z.rate"), HasSubstr("reads a slot"),
                    HasSubstr("as a load")));
  EXPECT_THAT(ErrorOf(Pendulum("states:\n  z: {rate: -z, unit: mm}\n")),
              AllOf(HasSubstr("states.z.unit = 'mm'"), HasSubstr("write `unit: m`")));
  EXPECT_THAT(ErrorOf(Pendulum("states:\n  z: {rate: -z, unit: furlong}\n")),
              HasSubstr("states.z.unit = 'furlong'"));
  EXPECT_THAT(ErrorOf(Pendulum("states:\n  th: {rate: 0}\n")),
              AllOf(HasSubstr("m.yaml:16: states.th"), HasSubstr("already used")));
  EXPECT_THAT(ErrorOf(Pendulum("states:\n  z: {rate: -z, initial: th}\n")),
              AllOf(HasSubstr("states.z.initial"), HasSubstr("a constant")));
  EXPECT_THAT(ErrorOf(Pendulum("states:\n  z: {rate: -zz}\n")),
              AllOf(HasSubstr("states.z.rate"), HasSubstr("did you mean")));
  EXPECT_THAT(ErrorOf(Pendulum("states:\n  z: -z\n")),
              AllOf(HasSubstr("states.z"), HasSubstr("{rate: <formula>")));
  EXPECT_THAT(ErrorOf(Pendulum("states:\n  z: {rate: -z, gain: 2}\n")), HasSubstr("'gain'"));
  // A state is not a coordinate: angles, positions and time functions may not read it.
  std::string angle = Pendulum("states:\n  z: {rate: -z}\n");
  angle.replace(angle.find("angle: th}"), 10, "angle: th + z}");
  EXPECT_THAT(ErrorOf(angle), AllOf(HasSubstr("m.yaml:8: frames[0].angle"), HasSubstr("a state")));
  EXPECT_THAT(ErrorOf(Pendulum("states:\n  z: {rate: -z}\ntime_functions:\n  f: 2 * z\n")),
              HasSubstr("time_functions.f"));
}

TEST(ModelFileStates, TheJacobianIsExactInTheStates) {
  const models::BuiltModel b = Build(Pendulum(
      "states:\n  z: {rate: \"(atan2(velocity(P, N).x, 1) - z * th) / 1 s\"}\n",
      "torques:\n  - {name: t, frame: A, value: [0, 0, \"-r1 - 3 * sin(z)\"]}\n"));
  Eigen::VectorXd x(3), r = Eigen::VectorXd::Constant(1, 2.0);
  x << 0.4, 0.9, -0.3;
  const Eigen::MatrixXd J = multibody::CalcStateJacobian(b.model, 0.0, x, r);
  multibody::Data<double> data(b.model);
  auto f = [&](const Eigen::VectorXd& xx) {
    Eigen::VectorXd out(3);
    multibody::CalcStateDerivative<double>(b.model, data, 0.0, xx, r, out);
    return out;
  };
  for (int k = 0; k < 3; ++k) {
    Eigen::VectorXd xp = x, xm = x;
    xp(k) += 1e-6;
    xm(k) -= 1e-6;
    EXPECT_LT((J.col(k) - (f(xp) - f(xm)) / 2e-6).cwiseAbs().maxCoeff(), 1e-7) << k;
  }
  EXPECT_NE(J(1, 2), 0.0);  // u̇ reads z
  EXPECT_NE(J(2, 0), 0.0);  // ż reads th
}

}  // namespace
}  // namespace hybridtest::modelfile
