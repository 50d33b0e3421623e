#pragma once
// The model's parameters as symbols in its printed equations (issue 36 item 2, decision 0019,
// "Parameters").
//
// The Model holds doubles (masses, inertias, the numbers its load lambdas captured), computed
// from the parameters when it is built, so the engine on Symbolic yields numbers where the
// model has parameters. SymbolizeParameters recovers them by rebuilding the model: each term
// of each simplified expression is c·(a product of q, u, t, r, z and functions of them). The
// parameters p_i ≠ 0 are taken in batches of up to twenty; one rebuild per batch scales every
// parameter of it by its own prime (2, 3, 5, …, 71), so a term whose coefficient is
// c = k · Π p_i^e_i (e_i whole or half) scales by Π prime_i^e_i, a fraction whose factors give
// every e_i of the batch at once (its square, or the ratio itself where the square's fraction is
// too large, found by continued fractions to 1e-13, the coefficients being exact to the model's
// rounding). A batch the model refuses (a scaled value out of its range) is rebuilt one
// parameter at a time; a parameter whose scaled value it refuses stays a number. A last rebuild
// with every parameter scaled by another factor at once checks each monomial (to 1e-9); k, if a
// small rational (denominator ≤ 1000, to 1e-12), is printed exactly. The rebuilds use the first
// derivation's symbols (DeriveEquations' `like`), so their terms compare without substitution.
//
// Angles (unit rad) are rebuilt one at a time after the batches: an angle inside a function
// (the built-in rotor's blade azimuth ψ_i in sin(q4 + ψ_i)) scales a term by no product of
// primes; its own rebuild shows that, and it is folded into the term's number (and left
// unscaled in the checking rebuild) while the term's other parameters stay symbols.
//
// A coefficient that is a sum of parameter products (the rotor's hub inertia I_g + 3 m_b l_b²
// becomes one number when the expression is expanded) or a parameter inside a function (an
// angle offset in cos(q + φ)) stays a number; the `parameters` list and dict give the values.
// Costs one derivation per batch of twenty parameters and per angle, plus one (issue 47; it
// was one per parameter, plus two).
#include <functional>
#include <string>
#include <vector>

#include "hybridtest/models/parameters.h"
#include "hybridtest/multibody/model.h"
#include "hybridtest/symbolic/equations.h"

namespace hybridtest::symbolic {

struct SymbolizeReport {
  int symbolic_terms = 0;  // terms whose coefficient became a product of parameters
  int numeric_terms = 0;   // terms whose coefficient depends on parameters but stays a number
};

// Whether `name` is an instance of a shared parameter ("blade2.m_b" of the rotor's "m_b")
// whose value it has, as every instance of it has: the equations print the shared symbol for
// all of them (issue 47 item 3: the substructure prefix only where instances differ), so the
// documents list the shared parameter only.
bool IsFollowingInstance(const models::ParameterSet& parameters, const std::string& name);

// Rewrites eq in place. `build` rebuilds the model from a parameter set (the same builder that
// made the model eq came from). Parameter symbols are named as the parameters; a parameter
// named like a coordinate, speed, slot, extra state or t stays a number.
SymbolizeReport SymbolizeParameters(
    Equations& eq, const models::ParameterSet& parameters,
    const std::function<multibody::Model(const models::ParameterSet&)>& build);

}  // namespace hybridtest::symbolic
