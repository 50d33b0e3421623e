// Named common subexpressions (shared.h): e and −e are one subexpression whatever form GiNaC
// holds them in, which is what keeps the printed order the same in every process (issue 47).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "hybridtest/symbolic/shared.h"

namespace hybridtest::symbolic {
namespace {

// a + b − x² and x² − a − b: GiNaC holds the first's x² term as the product (−1)·x² and the
// second's as the power x², so which of the two a process has (it depends on GiNaC's
// address-dependent term order, through the sign it takes out of a sum factor) must not change
// the sum's hash. They are one subexpression, named once, the other use its negation. Several
// names, since whether a wrong hash still picks opposite signs for the two is a coin toss.
TEST(SharedSubexpressions, SumAndItsNegationAreOneSubexpression) {
  const std::vector<std::vector<std::string>> names = {
      {"a", "b", "x"}, {"m", "g", "q1"}, {"cx", "cy", "q2"}, {"l1", "l2", "theta"},
      {"k", "c", "u1"}, {"p", "r", "z"}};
  for (const auto& n : names) {
    const GiNaC::realsymbol a(n[0]), b(n[1]), x(n[2]);
    GiNaC::ex e = a + b - GiNaC::pow(x, 2);
    GiNaC::ex minus_e = GiNaC::pow(x, 2) - a - b;
    const GiNaC::ex e0 = e;
    const SharedSubexpressions shared = ShareSubexpressions({&e, &minus_e}, "cse", {});
    ASSERT_EQ(shared.definitions.size(), 1U) << n[0] << " + " << n[1] << " - " << n[2] << "^2";
    EXPECT_TRUE((e + minus_e).is_zero()) << e << " and " << minus_e;
    EXPECT_TRUE((Inline(shared, e) - e0).is_zero()) << e;
  }
}

}  // namespace
}  // namespace hybridtest::symbolic
