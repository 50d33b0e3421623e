#pragma once
// The constrained part of a model's equations document (write_equations.h): the dependent
// speeds, the constraint rows A_d u_d + A_i u_i + b = 0, the acceleration constraints' bias
// Ḃ u + ċ, the symbols A = −A_d⁻¹ A_i and the reduced equations [Cᵀ M; B] u̇ = [Cᵀ f; −(Ḃ u + ċ)]
// (constrained.h), in Markdown, LaTeX or as SymPy statements.
//
// The SymPy statements define `dependent`, `independent` (lists of speed symbols),
// `constraint_rows` (their names), the sympy.Matrix objects `A_d`, `A_i`, `b`, `bias`, `A` (of
// the symbols A_s_c, A_d A = −A_i), `M_reduced` and `f_reduced`.
#include <string>

#include "hybridtest/multibody/model.h"
#include "hybridtest/symbolic/constrained.h"
#include "hybridtest/symbolic/print_expression.h"

namespace hybridtest::symbolic {

// The names of the A symbols in `dialect` (A_1_2; LaTeX A_{1,2}), added to `names`.
void AddConstrainedNames(const ConstrainedEquations& c, Dialect dialect, NameMap& names);

std::string ConstrainedMarkdown(const multibody::Model& model, const ConstrainedEquations& c,
                                const NameMap& names);
std::string ConstrainedLatex(const multibody::Model& model, const ConstrainedEquations& c,
                             const NameMap& names);
// The A symbols' definitions (sp.Symbol), to print with the other symbols.
std::string ConstrainedSympySymbols(const ConstrainedEquations& c, const NameMap& names);
// Everything else, after M and f.
std::string ConstrainedSympy(const multibody::Model& model, const ConstrainedEquations& c,
                             const NameMap& names);

}  // namespace hybridtest::symbolic
