#pragma once
// C code for a model's right-hand side (issue 36 item 3, decision 0019): one self-contained C
// function, `void NAME(double t, const double* x, const double* r, double* M, double* g,
// double* qdot, double* zdot)` (multibody::CompiledRhsFunction), that computes what the
// engine computes (DeriveRhs: M column-major, g, q̇, ż), straight-line, with every common
// subexpression computed once. A constrained model's C also defines `void NAME_constraints(double
// t, const double* x, double* B, double* velocity, double* position, double* bias)`
// (multibody::CompiledConstraintsFunction): the rows of B u + c = 0 as CalcConstraints computes
// them, with common subexpressions of their own; the reduction stays the engine's.
//
// Common subexpressions: GiNaC shares subtrees but does not expose that sharing for code, and
// has no CSE of its own. WriteC names them as the printed equations do (ShareSubexpressions,
// shared.h): every non-trivial subexpression used in two places (e and −e as one) becomes one
// `const double tK`, numbered in a canonical order, and every expression prints in
// PrintExpression's C dialect (terms in a fixed order, a sum factor in its canonical sign). So
// the text is the same bytes on every run (GiNaC's own term order and signs change between
// processes). A product or sum of two leaves (q1*u2) is written where it is used, not named;
// the compiler merges repeats.
//
// Refuses (ModelError, naming it) what C cannot compute: a model file's table (an uninterpreted
// function) or any function outside C's <math.h>.
#include <string>

#include "hybridtest/multibody/model.h"
#include "hybridtest/symbolic/equations.h"

namespace hybridtest::symbolic {

struct CCode {
  std::string source;      // the whole translation unit (includes <math.h> only)
  int temporaries = 0;     // common subexpressions (tK)
  int operations = 0;      // arithmetic operations and calls, after elimination
};

// `function_name` must be a C identifier. The source also defines `int NAME_n`, `NAME_nz`,
// `NAME_slots`, `NAME_m` (the sizes it was generated for; m constraint rows) and
// `const char NAME_model[]` (the model's name and summary), which the loader checks.
CCode WriteC(const multibody::Model& model, const RhsExpressions& rhs, const std::string& model_name,
             const std::string& function_name);

}  // namespace hybridtest::symbolic
