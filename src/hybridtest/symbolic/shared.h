#pragma once
// Common subexpressions of the printed equations, named in a fixed order (issue 47).
//
// Expanding the engine's expressions into sums of monomials (simplify.h) costs time and space
// exponential in the depth of a chain: a 6-link pendulum's mass matrix does not finish in
// minutes. ExpandedTerms estimates, without expanding, how many terms expansion would give;
// above kExpandLimit DeriveEquations keeps the engine's own expressions (its recursive
// structure: the rotation of link k built from link k − 1's) and ShareSubexpressions names
// every non-trivial subexpression used more than once, so that each is printed once.
//
// Order: GiNaC orders the operands of a sum or product by hashes that depend on addresses, so
// its order changes between processes; and its mul::eval takes the sign out of a sum that is a
// factor of a product by the sign of the sum's first term in that order, so one process holds
// y·(x − a) where another holds −y·(a − x). Neither reaches the output: e and −e are one
// subexpression (named once, by the sign of {e, −e} whose structural hash is lower), the
// intermediates are numbered in a depth-first walk that visits the operands sorted by a
// structural hash of names, numbers and operators only (CanonicalHash, the same for e and
// −e), and the printer orders terms by their text and prints a sum factor in its canonical
// sign (print_expression.h). Two runs print the same bytes (tested: `equations_stable`).
#include <ginac/ginac.h>

#include <cstdint>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace hybridtest::symbolic {

// Above this many terms (estimated over every printed expression) the equations are not
// expanded but printed with named common subexpressions.
inline constexpr double kExpandLimit = 20000.0;

// An upper estimate of the number of terms of e.expand() (a sum of n terms to the power k
// counts n^k; functions count 1), capped at 1e15. Linear in the number of distinct
// subexpressions.
double ExpandedTerms(const std::vector<GiNaC::ex>& expressions);

// A hash of e's structure that does not depend on addresses or on GiNaC's operand order:
// symbols by name, numbers by value, sums and products by the sorted hashes of their operands
// (a product ±1·x as x), a sum in the sign of {e, −e} that hashes lower (with that sign mixed
// in: e and −e differ).
std::uint64_t CanonicalHash(const GiNaC::ex& e);

struct SharedSubexpressions {
  // (symbol, definition) in the order they must be computed: a definition uses only the
  // model's symbols and earlier intermediates.
  std::vector<std::pair<GiNaC::ex, GiNaC::ex>> definitions;
};

// Rewrites every *output (in place) in terms of new symbols, one for each subexpression used
// more than once (e and −e counting as one: −e is used as −symbol) that is not trivial (a number, a symbol, or a sum, product or power of two
// numbers or symbols). The symbols are named "<prefix>1", "<prefix>2", … (with a trailing '_'
// added while a name is in `reserved`). Floats that are exact dyadic fractions become
// rationals (simplify.h).
SharedSubexpressions ShareSubexpressions(const std::vector<GiNaC::ex*>& outputs,
                                         const std::string& prefix,
                                         const std::set<std::string>& reserved);

// `e` with every intermediate replaced by its definition (for checks; exponential in the
// worst case on deep equations, as expansion is).
GiNaC::ex Inline(const SharedSubexpressions& shared, const GiNaC::ex& e);

}  // namespace hybridtest::symbolic
