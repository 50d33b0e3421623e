#pragma once
// A Butcher tableau: the data that defines a Runge–Kutta method (odeint's first layer). It holds
// no state and does no stepping; ExplicitRungeKutta (explicit_runge_kutta.h) steps with it.
//
// An s-stage method is written
//
//     c_0     | a_00      a_01      …  a_0,s-1
//     c_1     | a_10      a_11      …  a_1,s-1
//     ⋮       | ⋮                       ⋮
//     c_s-1   | a_s-1,0   a_s-1,1   …  a_s-1,s-1
//     --------+-----------------------------------
//             | b_0       b_1       …  b_s-1
//
// and is explicit when a is strictly lower triangular (a_ij = 0 for j ≥ i). Indices are 0-based
// here and in error messages (a[i][j], b[i], c[i]), as in a config file's nested lists.
#include <string>
#include <string_view>

#include <Eigen/Core>

namespace hybridtest::integrators {

struct ButcherTableau {
  std::string name;   // catalogue key, e.g. "heun"
  std::string title;  // human name, e.g. "Heun's method (explicit trapezoidal rule)"
  Eigen::MatrixXd a;  // (s × s) stage coefficients; strictly lower triangular for explicit methods
  Eigen::VectorXd b;  // (s) weights
  Eigen::VectorXd c;  // (s) nodes, c_i = Σ_j a_ij. Unit: fraction of the step h [-]
  int order = 0;      // classical order p claimed: the global error is O(h^p)

  // Number of stages s, i.e. right-hand-side evaluations per step (= b.size()).
  int stages() const { return static_cast<int>(b.size()); }
};

// Absolute tolerance for the row-sum condition c_i = Σ_j a_ij and for the order conditions.
// Entries must therefore be given to (nearly) full double precision: 0.3333 is not 1/3.
inline constexpr double kTableauTolerance = 1e-12;

// Highest classical order ValidateTableau can check (all rooted trees up to 4 nodes).
inline constexpr int kMaxCheckedOrder = 4;

// Throws ConfigError naming `where` (e.g. "examples/x.yaml: integrator.tableau") and the
// offending entry when:
//   - shapes disagree: a is not s × s, or b, c do not have s entries, or s = 0;
//   - an entry of a, b or c is not finite (NaN, ±inf);
//   - a is not strictly lower triangular (only explicit methods are supported);
//   - c_i != Σ_j a_ij (tolerance kTableauTolerance);
//   - order < 1, or order > kMaxCheckedOrder (not supported: the conditions are not checked);
//   - an order condition up to the claimed order p is violated (tolerance kTableauTolerance):
//       p ≥ 1:  Σ b_i = 1
//       p ≥ 2:  Σ b_i c_i = 1/2
//       p ≥ 3:  Σ b_i c_i² = 1/3,        Σ b_i a_ij c_j = 1/6
//       p ≥ 4:  Σ b_i c_i³ = 1/4,        Σ b_i c_i a_ij c_j = 1/8,
//               Σ b_i a_ij c_j² = 1/12,  Σ b_i a_ij a_jk c_k = 1/24
// The checks run in the order listed; the first failure is reported. Returns normally when the
// tableau is a valid explicit method of (at least) the claimed order.
void ValidateTableau(const ButcherTableau& tableau, std::string_view where);

}  // namespace hybridtest::integrators
