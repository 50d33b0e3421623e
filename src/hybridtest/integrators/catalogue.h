#pragma once
// The built-in explicit Runge–Kutta methods, looked up by name (the config key
// `integrator.method`). Every entry passes ValidateTableau; the tests check each one's order of
// convergence by integrating an ODE with a known solution, table-driven over Catalogue(), so a
// new entry is tested by just being added (see docs/adding-an-integrator.md).
//
// Nodes c on the left, stage coefficients a in the middle, weights b at the bottom; p is the
// classical order, s the number of stages (substructure trials per step).
//
//   "euler"     forward Euler                         p = 1, s = 1
//       0 |
//       --+---
//         | 1
//
//   "heun"      Heun's method (explicit trapezoidal)   p = 2, s = 2
//       0 |
//       1 | 1
//       --+---------
//         | 1/2  1/2
//
//   "midpoint"  explicit midpoint rule                 p = 2, s = 2
//       0   |
//       1/2 | 1/2
//       ----+---------
//           | 0    1
//
//   "ralston"   Ralston's second-order method          p = 2, s = 2
//       0   |                  (minimizes the bound of the leading error term among 2-stage
//       2/3 | 2/3               second-order methods)
//       ----+---------
//           | 1/4  3/4
//
//   "rk3"       Kutta's third-order method             p = 3, s = 3
//       0   |
//       1/2 | 1/2
//       1   | -1   2
//       ----+--------------
//           | 1/6  2/3  1/6
//
//   "rk4"       classical Runge–Kutta                  p = 4, s = 4
//       0   |
//       1/2 | 1/2
//       1/2 | 0    1/2
//       1   | 0    0    1
//       ----+-------------------
//           | 1/6  1/3  1/3  1/6
//
//   "rk38"      Kutta's 3/8 rule                        p = 4, s = 4
//       0   |
//       1/3 | 1/3
//       2/3 | -1/3 1
//       1   | 1    -1   1
//       ----+-------------------
//           | 1/8  3/8  3/8  1/8
//
// The paper's hybrid test used a second-order method (s = 2) at h = 1 ms.
#include <string>
#include <string_view>
#include <vector>

#include "hybridtest/integrators/butcher_tableau.h"

namespace hybridtest::integrators {

// All built-in tableaus, in the order listed above. Built once; the reference stays valid for
// the life of the program.
const std::vector<ButcherTableau>& Catalogue();

// The names (catalogue keys) of all built-in tableaus, in catalogue order.
std::vector<std::string> TableauNames();

// The built-in tableau called `name` (exact, case-sensitive match). Throws ConfigError when
// there is none; the message lists the known names and suggests the closest one.
const ButcherTableau& FindTableau(std::string_view name);

}  // namespace hybridtest::integrators
