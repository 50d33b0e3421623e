// Dimensions through model-file formulas: what carries a unit is followed through the tree and
// checked where the formula is used; bare numbers and parameters without a unit match anything.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "hybridtest/common/error.h"
#include "hybridtest/modelfile/model_file.h"
#include "support/model_file_error.h"

namespace hybridtest::modelfile {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

// A pendulum on a cart; `position` is P's x, `rest` follows line 17.
std::string Model(const std::string& position, const std::string& rest = "") {
  return "name: p\n"                                                       // 1
         "parameters:\n"                                                   // 2
         "  L: {value: 600, unit: mm}\n"                                   // 3
         "  m_b: {value: 2, unit: kg}\n"                                   // 4
         "  k: {value: 5, unit: kN/m}\n"                                   // 5
         "  V0: {value: 8, unit: m/s}\n"                                   // 6
         "  plain: 3\n"                                                    // 7
         "coordinates:\n"                                                  // 8
         "  - {name: th, unit: rad}\n"                                     // 9
         "  - {name: x, unit: m}\n"                                        // 10
         "frames:\n"                                                       // 11
         "  - {name: A, parent: N, axis: z, angle: th}\n"                  // 12
         "points:\n"                                                       // 13
         "  - {name: C, from: O, frame: N, position: [x, 0, 0]}\n"         // 14
         "  - {name: P, from: C, frame: A, position: [\"" + position + "\", 0, 0]}\n"  // 15
         "particles:\n"                                                    // 16
         "  - {name: bob, point: P, mass: m_b}\n"                          // 17
         + rest;
}

std::string ErrorOf(const std::string& text) { return ::test_support::ModelFileError(text); }

TEST(ModelFileDimensions, ConsistentFormulasPass) {
  EXPECT_EQ(ErrorOf(Model("L * cos(th) + x")), "no error");
  EXPECT_EQ(ErrorOf(Model("L + V0 * t")), "no error");
  EXPECT_EQ(ErrorOf(Model("sqrt(L^2 + x^2)")), "no error");
  EXPECT_EQ(ErrorOf(Model("L * atan2(x, L) + 2")), "no error");  // a bare number: unknown
  EXPECT_EQ(ErrorOf(Model("plain * m_b")), "no error");          // no unit: unknown
  EXPECT_EQ(ErrorOf(Model("L", "forces:\n  - {name: f, point: P, value: [\"-k * x - 50 * sign(velocity(P, N).x)\", 0, 0]}\n"
                               "torques:\n  - {name: t, frame: A, value: [0, 0, \"-k * L^2 * th + 3 N·m * sin(th)\"]}\n")),
            "no error");
}

TEST(ModelFileDimensions, MismatchesAreRefusedWithBothUnits) {
  EXPECT_THAT(ErrorOf(Model("m_b")),
              AllOf(HasSubstr("m.yaml:15: points[1].position[0] = 'm_b'"), HasSubstr("is in kg"),
                    HasSubstr("but m is expected")));
  EXPECT_THAT(ErrorOf(Model("L + t")),
              AllOf(HasSubstr("points[1].position[0] = 'L + t': at '+' (column 3)"),
                    HasSubstr("a quantity in m and one in s")));
  EXPECT_THAT(ErrorOf(Model("L * cos(L)")), HasSubstr("at 'cos' (column 5)"));
  EXPECT_THAT(ErrorOf(Model("L * sin(x)")),
              AllOf(HasSubstr("argument of this function is in m"), HasSubstr("dimensionless")));
  EXPECT_THAT(ErrorOf(Model("sqrt(L)")), HasSubstr("fractional or variable unit"));
  EXPECT_THAT(ErrorOf(Model("L * max(x, t)")), HasSubstr("min() or max()"));
  EXPECT_THAT(ErrorOf(Model("if(x < t, L, L)")), HasSubstr("the condition compares"));
  EXPECT_THAT(ErrorOf(Model("if(x < L, L, V0)")), HasSubstr("branches of if()"));
  EXPECT_THAT(ErrorOf(Model("L", "forces:\n  - {name: f, point: P, value: [\"-k * th\", 0, 0]}\n")),
              AllOf(HasSubstr("m.yaml:19: forces[0].value[0]"), HasSubstr("is in kg/s²"),
                    HasSubstr("kg·m/s² is expected")));
  EXPECT_THAT(ErrorOf(Model("L", "torques:\n  - {name: t, frame: A, value: [0, 0, \"-k * x\"]}\n")),
              AllOf(HasSubstr("torques[0].value[2]"), HasSubstr("kg·m²/s² is expected")));
  std::string angle = Model("L");
  angle.replace(angle.find("angle: th}"), 10, "angle: th + x}");
  EXPECT_THAT(ErrorOf(angle), AllOf(HasSubstr("m.yaml:12: frames[0].angle"), HasSubstr("a quantity in 1 and one in m")));
  std::string mass = Model("L");
  mass.replace(mass.find("mass: m_b}"), 10, "mass: L}");
  EXPECT_THAT(ErrorOf(mass), AllOf(HasSubstr("particles[0].mass"), HasSubstr("kg is expected")));
  EXPECT_THAT(ErrorOf(Model("L", "slots:\n  - {name: r1, unit: N, displacement: th, stiffness: k}\n")),
              AllOf(HasSubstr("slots[0].displacement"), HasSubstr("m is expected")));
  EXPECT_THAT(ErrorOf(Model("L", "slots:\n  - {name: r1, unit: N·m, displacement: th, stiffness: k}\n")),
              AllOf(HasSubstr("slots[0].stiffness"), HasSubstr("kg·m²/s² is expected")));
  EXPECT_THAT(ErrorOf(Model("L", "states:\n  z: {rate: x, unit: m}\n")),
              AllOf(HasSubstr("states.z.rate"), HasSubstr("m/s is expected")));
  // A time function's dimension comes from its formula.
  EXPECT_EQ(ErrorOf(Model("L", "time_functions:\n  s: V0 * t\n"
                                "forces:\n  - {name: f, point: P, value: [k * s, 0, 0]}\n")),
            "no error");
  EXPECT_THAT(ErrorOf(Model("L", "time_functions:\n  s: V0 * t\n"
                                 "forces:\n  - {name: f, point: P, value: [s, 0, 0]}\n")),
              HasSubstr("forces[0].value[0] = 's': is in m"));
}

}  // namespace
}  // namespace hybridtest::modelfile
