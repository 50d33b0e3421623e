// ValidateTableau: accepts valid explicit methods, and rejects each kind of bad tableau with a
// message that names the problem, the offending entry and the `where` it was given.
#include "hybridtest/integrators/butcher_tableau.h"

#include <limits>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "hybridtest/common/error.h"

namespace hybridtest::integrators {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

constexpr char kWhere[] = "examples/x.yaml: integrator.tableau";

// Heun's method, written here independently of the catalogue.
ButcherTableau Heun() {
  ButcherTableau t;
  t.name = "my_heun";
  t.a = Eigen::MatrixXd::Zero(2, 2);
  t.a(1, 0) = 1.0;
  t.b = Eigen::Vector2d(0.5, 0.5);
  t.c = Eigen::Vector2d(0.0, 1.0);
  t.order = 2;
  return t;
}

// Kutta's third-order method, written here independently of the catalogue.
ButcherTableau Kutta3() {
  ButcherTableau t;
  t.name = "my_rk3";
  t.a = Eigen::MatrixXd::Zero(3, 3);
  t.a(1, 0) = 0.5;
  t.a(2, 0) = -1.0;
  t.a(2, 1) = 2.0;
  t.b = Eigen::Vector3d(1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0);
  t.c = Eigen::Vector3d(0.0, 0.5, 1.0);
  t.order = 3;
  return t;
}

// The message of the ConfigError that ValidateTableau throws; fails the test if it throws none.
std::string RejectionMessage(const ButcherTableau& t) {
  try {
    ValidateTableau(t, kWhere);
  } catch (const ConfigError& e) {
    return e.what();
  }
  ADD_FAILURE() << "ValidateTableau accepted an invalid tableau";
  return "";
}

TEST(ValidateTableau, AcceptsValidMethods) {
  EXPECT_NO_THROW(ValidateTableau(Heun(), kWhere));
  EXPECT_NO_THROW(ValidateTableau(Kutta3(), kWhere));
  // A claim below the true order is honest (order 3 method claimed as order 2).
  ButcherTableau under_claimed = Kutta3();
  under_claimed.order = 2;
  EXPECT_NO_THROW(ValidateTableau(under_claimed, kWhere));
}

TEST(ValidateTableau, RejectsWrongShapes) {
  ButcherTableau wide = Heun();
  wide.a = Eigen::MatrixXd::Zero(2, 3);
  EXPECT_THAT(RejectionMessage(wide),
              AllOf(HasSubstr(kWhere), HasSubstr("my_heun"), HasSubstr("shapes disagree"),
                    HasSubstr("given a 2 × 3")));

  ButcherTableau long_c = Heun();
  long_c.c = Eigen::Vector3d(0.0, 1.0, 1.0);
  EXPECT_THAT(RejectionMessage(long_c),
              AllOf(HasSubstr(kWhere), HasSubstr("c with 3 entries")));

  ButcherTableau empty;
  empty.order = 1;
  EXPECT_THAT(RejectionMessage(empty), AllOf(HasSubstr(kWhere), HasSubstr("at least one stage")));
}

TEST(ValidateTableau, RejectsNonFiniteEntries) {
  ButcherTableau nan_b = Heun();
  nan_b.b(0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THAT(RejectionMessage(nan_b),
              AllOf(HasSubstr(kWhere), HasSubstr("b[0]"), HasSubstr("finite")));

  ButcherTableau inf_a = Heun();
  inf_a.a(1, 0) = std::numeric_limits<double>::infinity();
  EXPECT_THAT(RejectionMessage(inf_a),
              AllOf(HasSubstr(kWhere), HasSubstr("a[1][0]"), HasSubstr("finite")));

  ButcherTableau nan_c = Heun();
  nan_c.c(1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THAT(RejectionMessage(nan_c), AllOf(HasSubstr("c[1]"), HasSubstr("finite")));
}

TEST(ValidateTableau, RejectsNonLowerTriangularA) {
  ButcherTableau upper = Heun();
  upper.a(0, 1) = 0.5;
  upper.c(0) = 0.5;  // keep the row sums consistent: only the shape of a is wrong
  EXPECT_THAT(RejectionMessage(upper),
              AllOf(HasSubstr(kWhere), HasSubstr("a[0][1]"),
                    HasSubstr("strictly lower triangular")));

  // A diagonal entry makes the method implicit, which is not supported either.
  ButcherTableau diagonal = Heun();
  diagonal.a(1, 1) = 0.25;
  diagonal.c(1) = 1.25;
  EXPECT_THAT(RejectionMessage(diagonal),
              AllOf(HasSubstr("a[1][1]"), HasSubstr("strictly lower triangular")));
}

TEST(ValidateTableau, RejectsInconsistentNodes) {
  ButcherTableau t = Heun();
  t.c(1) = 0.9;
  EXPECT_THAT(RejectionMessage(t),
              AllOf(HasSubstr(kWhere), HasSubstr("c[1] = 0.9"), HasSubstr("row sum")));

  // Within the tolerance of 1e-12 is accepted; beyond it is not.
  t.c(1) = 1.0 + 0.5e-12;
  EXPECT_NO_THROW(ValidateTableau(t, kWhere));
  t.c(1) = 1.0 + 1e-10;
  EXPECT_THAT(RejectionMessage(t), HasSubstr("c[1]"));
}

TEST(ValidateTableau, RejectsUnsupportedOrderClaims) {
  ButcherTableau zero = Heun();
  zero.order = 0;
  EXPECT_THAT(RejectionMessage(zero), AllOf(HasSubstr(kWhere), HasSubstr("order = 0")));

  ButcherTableau five = Heun();
  five.order = 5;
  EXPECT_THAT(RejectionMessage(five),
              AllOf(HasSubstr(kWhere), HasSubstr("order = 5"), HasSubstr("not supported")));
}

TEST(ValidateTableau, RejectsOrderOneViolation) {
  ButcherTableau t = Heun();
  t.b = Eigen::Vector2d(0.5, 0.6);
  t.order = 1;
  EXPECT_THAT(RejectionMessage(t), AllOf(HasSubstr("order-1 condition"), HasSubstr("Σ b_i = 1")));
}

TEST(ValidateTableau, RejectsOrderTwoViolation) {
  ButcherTableau t = Heun();
  t.b = Eigen::Vector2d(0.75, 0.25);  // consistent (Σb = 1) but only first order
  EXPECT_THAT(RejectionMessage(t),
              AllOf(HasSubstr(kWhere), HasSubstr("claims order 2"),
                    HasSubstr("Σ b_i c_i = 1/2")));
}

TEST(ValidateTableau, RejectsOrderThreeClaimOfSecondOrderMethod) {
  ButcherTableau t = Heun();
  t.order = 3;
  EXPECT_THAT(RejectionMessage(t),
              AllOf(HasSubstr(kWhere), HasSubstr("claims order 3"), HasSubstr("order-3 condition"),
                    HasSubstr("Σ b_i c_i² = 1/3")));
}

TEST(ValidateTableau, ChecksTheTreeConditionNotOnlyTheQuadrature) {
  // Same b and c as Kutta's method (so Σ b c² = 1/3 holds) and consistent row sums, but the
  // last row of a changed: only Σ b_i a_ij c_j = 1/6 is violated.
  ButcherTableau t = Kutta3();
  t.a(2, 0) = 0.0;
  t.a(2, 1) = 1.0;
  EXPECT_THAT(RejectionMessage(t), HasSubstr("Σ b_i a_ij c_j = 1/6"));
}

TEST(ValidateTableau, ChecksAllFourthOrderConditions) {
  // Kutta's third-order method happens to satisfy Σ b c³ = 1/4, so a claim of order 4 must be
  // caught by a later p = 4 condition.
  ButcherTableau t = Kutta3();
  t.order = 4;
  EXPECT_THAT(RejectionMessage(t),
              AllOf(HasSubstr("claims order 4"), HasSubstr("Σ b_i c_i a_ij c_j = 1/8")));
}

}  // namespace
}  // namespace hybridtest::integrators
