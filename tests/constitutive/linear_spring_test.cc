#include "hybridtest/constitutive/linear_spring.h"

#include <cmath>

#include <gtest/gtest.h>

#include "hybridtest/common/error.h"
#include "hybridtest/constitutive/cantilever.h"

namespace hybridtest::constitutive {
namespace {

TEST(LinearSpring, ForceIsStiffnessTimesDisplacement) {
  LinearSpring spring(7200.0);
  EXPECT_DOUBLE_EQ(spring.Trial(0.01), 72.0);
  EXPECT_DOUBLE_EQ(spring.Trial(-0.002), -14.4);
  EXPECT_DOUBLE_EQ(spring.initial_stiffness(), 7200.0);
  EXPECT_NE(spring.Describe().find("7200"), std::string::npos);
}

TEST(LinearSpring, CloneIsIndependentAndEqual) {
  LinearSpring spring(100.0, "custom");
  auto copy = spring.Clone();
  EXPECT_DOUBLE_EQ(copy->Trial(0.5), 50.0);
  EXPECT_EQ(copy->Describe(), "custom");
}

TEST(LinearSpring, RejectsNonFiniteStiffness) {
  EXPECT_THROW(LinearSpring(std::nan("")), ConfigError);
}

TEST(Cantilever, PapersSteelBeamIsAbout5250NewtonPerMetre) {
  // 500 x 100 x 5 mm, E = 210 GPa: I = 0.1 * 0.005^3 / 12 = 1.0417e-9 m^4, k = 3EI/L^3.
  EXPECT_NEAR(CantileverTipStiffness(0.5, 0.1, 0.005, 210e9), 5250.0, 1e-9);
}

TEST(Cantilever, ScalesWithCubeOfThicknessAndInverseCubeOfLength) {
  const double k = CantileverTipStiffness(0.5, 0.1, 0.005, 210e9);
  EXPECT_NEAR(CantileverTipStiffness(0.5, 0.1, 0.010, 210e9) / k, 8.0, 1e-12);
  EXPECT_NEAR(CantileverTipStiffness(1.0, 0.1, 0.005, 210e9) / k, 0.125, 1e-12);
  EXPECT_NEAR(CantileverTipStiffness(0.5, 0.2, 0.005, 210e9) / k, 2.0, 1e-12);
}

TEST(Cantilever, SpringDescribesTheBeam) {
  auto spring = MakeCantileverSpring(0.5, 0.1, 0.005, 210e9);
  EXPECT_NEAR(spring->stiffness(), 5250.0, 1e-9);
  EXPECT_NE(spring->Describe().find("500x100x5 mm"), std::string::npos) << spring->Describe();
}

TEST(Cantilever, RejectsNonPositiveDimensions) {
  EXPECT_THROW(CantileverTipStiffness(0.0, 0.1, 0.005, 210e9), ConfigError);
  EXPECT_THROW(CantileverTipStiffness(0.5, -0.1, 0.005, 210e9), ConfigError);
  EXPECT_THROW(CantileverTipStiffness(0.5, 0.1, 0.005, std::nan("")), ConfigError);
}

}  // namespace
}  // namespace hybridtest::constitutive
