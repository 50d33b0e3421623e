#include "hybridtest/constitutive/parse_law.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "hybridtest/common/error.h"
#include "hybridtest/constitutive/bouc_wen.h"

namespace hybridtest::constitutive {
namespace {

using ::testing::HasSubstr;

std::unique_ptr<RestoringForceLaw> Parse(const std::string& text) {
  return ParseRestoringForceLaw(YAML::Load(text), "test.yaml: specimen");
}

std::string ErrorOf(const std::string& text) {
  try {
    Parse(text);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ParseRestoringForceLaw, Linear) {
  auto law = Parse("{type: linear, stiffness: 7200}");
  EXPECT_DOUBLE_EQ(law->Trial(0.001), 7.2);
}

TEST(ParseRestoringForceLaw, CantileverIsThePapersBeam) {
  auto law = Parse("{type: cantilever, length: 0.5, width: 0.1, thickness: 0.005, "
                   "youngs_modulus: 210e9}");
  EXPECT_NEAR(law->initial_stiffness(), 5250.0, 1e-9);
}

TEST(ParseRestoringForceLaw, BoucWenBothForms) {
  auto yield = Parse("{type: bouc_wen, initial_stiffness: 5000, alpha: 0.1, "
                     "yield_displacement: 0.002, n: 2}");
  auto* bw = dynamic_cast<BoucWen*>(yield.get());
  ASSERT_NE(bw, nullptr);
  EXPECT_NEAR(bw->ultimate_z(), 0.002, 1e-15);
  auto classic = Parse("{type: bouc_wen, initial_stiffness: 5000, alpha: 0.1, A: 1, "
                       "beta: 250, gamma: 250, n: 1}");
  EXPECT_NEAR(dynamic_cast<BoucWen&>(*classic).ultimate_z(), 0.002, 1e-15);
}

TEST(ParseRestoringForceLaw, ErrorsNameKeyPathAndFix) {
  EXPECT_THAT(ErrorOf("{type: linear}"), HasSubstr("test.yaml: specimen.stiffness: missing"));
  EXPECT_THAT(ErrorOf("{type: linear, stiffness: abc}"),
              HasSubstr("specimen.stiffness (line 1) = 'abc': expected"));
  EXPECT_THAT(ErrorOf("{type: spring, stiffness: 1}"),
              HasSubstr("one of linear, cantilever, bouc_wen"));
  EXPECT_THAT(ErrorOf("{type: linear, stifness: 1}"), HasSubstr("specimen.stifness"));
  EXPECT_THAT(ErrorOf("{stiffness: 1}"), HasSubstr("specimen.type: missing"));
  EXPECT_THAT(ErrorOf("{type: cantilever, length: -0.5, width: 0.1, thickness: 0.005, "
                      "youngs_modulus: 210e9}"),
              HasSubstr("test.yaml: specimen: cantilever: length = -0.5"));
  EXPECT_THAT(ErrorOf("{type: bouc_wen, initial_stiffness: 1, alpha: 0.1}"),
              HasSubstr("neither was given"));
  EXPECT_THAT(ErrorOf("[1, 2]"), HasSubstr("expected a mapping"));
}

}  // namespace
}  // namespace hybridtest::constitutive
