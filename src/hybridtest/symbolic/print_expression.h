#pragma once
// One expression as text, in one of three dialects (decision 0019):
//   kPlain  — for Markdown: a·b, x^2, sin(q1), 1/2, numbers as decimals;
//   kLatex  — for LaTeX math mode: \sin{\left(q_{1} \right)}, \frac{a}{b}, \dot{u}_{1};
//   kSympy  — a Python expression over `sp` (import sympy as sp) and the module's symbol
//             variables: sp.sin(q1), x**2, sp.Rational(1, 2);
//   kC      — a C expression over <math.h> (codegen.h): sin(q1), x*x, pow(x, 5.0), fabs(x),
//             every number a double literal C reads back exactly (17 significant digits,
//             never an int: 0.5, not 1/2). A function C lacks (a model file's table) or a
//             complex number throws ModelError.
// Symbols print through a name map (symbol name → text); a symbol missing from it prints its
// own name. GiNaC's own printers are not used: they print doubles with 17 significant digits
// and know neither SymPy's function names nor the model's display names.
#include <ginac/ginac.h>

#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace hybridtest::symbolic {

enum class Dialect { kPlain, kLatex, kSympy, kC };

using NameMap = std::map<std::string, std::string>;

// The terms of a sum (and the factors of a product) print in a fixed order, sorted by their
// text: the same expression prints the same on every run (GiNaC's order is by address
// hashes). A sum that is a factor (or a whole power's base) prints in the sign that makes its
// first term positive, the product's sign adjusted: GiNaC stores y·(x − a) as −y·(a − x) in
// some processes, and both print `-(a - x)*y`. Every negative term prints with a leading '-'
// (`-sp.Rational(1, 2)`). Floats print with at most 15 significant digits (1.57, not
// 1.5699999999999998), except in kC.
std::string PrintExpression(const GiNaC::ex& e, Dialect dialect, const NameMap& names);

// The terms of e if it is a sum (else e alone), printed, in PrintExpression's order.
std::vector<std::string> PrintTerms(const GiNaC::ex& e, Dialect dialect, const NameMap& names);

// A name as LaTeX: Greek letters get their macro, a trailing number or `_x` part becomes a
// subscript, `_dot` an over-dot ("theta2" → "\theta_{2}", "u1_dot" → "\dot{u}_{1}").
std::string LatexName(const std::string& name);

// `text` for LaTeX's text mode (inside \section, \paragraph, \texttt): its special characters
// \ { } $ & # % _ ^ ~ written as their macros or escapes, control characters as spaces, so
// that no text can open a macro (\input, \write18) or leave the group it is printed in.
std::string LatexText(std::string_view text);

// `text` as the inside of a Python string literal (single, double or triple quoted): \, ' and "
// escaped, control characters as \xNN. PythonString adds the single quotes.
std::string PythonStringBody(std::string_view text);
std::string PythonString(std::string_view text);

// `text` for a Python comment: control characters (a newline would end the comment) as spaces.
std::string PythonComment(std::string_view text);

// A valid Python identifier for `name`, distinct from the module's own names (sp, q, u, r, t,
// M, f, parameters, ...): other characters become '_', a clash gets a trailing '_'.
std::string PythonName(const std::string& name);

}  // namespace hybridtest::symbolic
