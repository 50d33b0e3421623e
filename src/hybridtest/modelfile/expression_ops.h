// The built-in functions of model-file expressions and the folding of constant operations,
// shared by the parser (expression_parser.cc) and expression.cc. Internal to the layer.
#pragma once

#include <span>
#include <string_view>

#include "hybridtest/modelfile/expression.h"

namespace hybridtest::modelfile {

struct FunctionInfo {
  const char* name;
  Op op;
  int arity;  // number of arguments
};

// Every function an expression may call.
std::span<const FunctionInfo> KnownFunctions();
// The same as a phrase for error messages.
std::string_view KnownFunctionList();

// Value of a unary or binary operation on constants (b is ignored for a unary one).
double Fold(Op op, double a, double b);

}  // namespace hybridtest::modelfile
