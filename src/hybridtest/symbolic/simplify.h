#pragma once
// Simplification of the engine's symbolic results for printing (decision 0019).
//
// The engine's arithmetic leaves floating-point numbers (a model's parameters are doubles,
// decision 0019) and unsimplified trigonometry (a rotation matrix times its transpose). Simplify:
//   1. replaces floats that are exact dyadic fractions (0.5, 2.0, −1.0) by exact rationals;
//   2. expands;
//   3. applies sin(x)² = 1 − cos(x)² (on every power ≥ 2) and expands again, so that a sum that
//      is constant by the Pythagorean identity collapses;
//   4. drops the terms of a sum whose numeric coefficient is below 1e-13 times the sum's
//      largest (the rounding left by step 3 on float coefficients such as cos²ψ + sin²ψ − 1),
//      and snaps floats within 1e-13 (relative) of a dyadic fraction to it.
// The result equals the input up to those roundings (≤ 1e-13 relative per coefficient).
#include <ginac/ginac.h>

#include <unordered_map>
#include <utility>

namespace hybridtest::symbolic {

GiNaC::ex Simplify(const GiNaC::ex& e);

// Simplify for many expressions that share subexpressions (the engine's outputs share their
// points' partial velocities, rotation matrices, …): steps 1 and 2 are done once per shared
// subexpression (GiNaC's expand would expand a shared one again in every expression holding
// it), so that simplifying them all costs about as much as their distinct parts. The same
// results as Simplify, term for term.
class Simplifier {
 public:
  GiNaC::ex operator()(const GiNaC::ex& e);

 private:
  GiNaC::ex Expanded(const GiNaC::ex& e);
  // by the subexpression's object: (the subexpression, kept alive so that its address is not
  // reused; its exact, expanded form)
  std::unordered_map<const GiNaC::basic*, std::pair<GiNaC::ex, GiNaC::ex>> expanded_;
};

// A float that is exactly a dyadic fraction k/1024 (0.5, 2.0, −1.0) as that rational; any
// other number as it is.
GiNaC::ex ExactDyadic(const GiNaC::numeric& n);

}  // namespace hybridtest::symbolic
