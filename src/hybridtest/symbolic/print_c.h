#pragma once
// The C dialect of PrintExpression (print_expression.h, Dialect::kC; codegen.h): the parts of
// an expression's text that only C has: double literals, <math.h> calls and whole powers.
// PrintExpression's printer composes them; everything else (term order, signs, products) is
// shared with the other dialects.
#include <ginac/ginac.h>

#include <string>

namespace hybridtest::symbolic::c_print {

// A double literal that C reads back exactly (17 significant digits), always with a point or
// an exponent so that C never takes it for an int (1/2 would be 0). Throws ModelError for a
// complex number.
std::string Literal(const GiNaC::numeric& n);

// The call of GiNaC's function `name` on the printed, comma-separated `arguments`, in C
// (sin → sin, abs → fabs, csgn written out as a comparison). Throws ModelError, naming the
// function, for one C lacks (a model file's 1-D table).
std::string Call(const std::string& name, const std::string& arguments);

// base^exponent: a whole exponent from 2 to 4 as a product of `wrapped_base` (the base
// parenthesised as a factor; *is_product set), else pow(base, exponent_text) (an atom).
std::string Power(const std::string& base, const std::string& wrapped_base,
                  const GiNaC::ex& exponent, const std::string& exponent_text, bool* is_product);

}  // namespace hybridtest::symbolic::c_print
