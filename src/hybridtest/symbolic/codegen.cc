// C code with common subexpressions eliminated. See codegen.h.
#include "hybridtest/symbolic/codegen.h"

#include <fmt/core.h>
#include <ginac/ginac.h>

#include <algorithm>
#include <cctype>
#include <set>
#include <string_view>
#include <utility>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/symbolic/print_expression.h"
#include "hybridtest/symbolic/shared.h"

namespace hybridtest::symbolic {

namespace {

// A name as it may stand in a C comment and string literal: letters, digits and " _-.,:()"
// only, every other byte '_' (so no quote, backslash, newline or "*/").
std::string CText(const std::string& name) {
  std::string s;
  for (char c : name) {
    const bool plain = std::isalnum(static_cast<unsigned char>(c)) || std::string_view(" _-.,:()").find(c) != std::string_view::npos;
    s += plain ? c : '_';
  }
  return s;
}

bool IsCIdentifier(const std::string& name) {
  if (name.empty() || name.size() > 64 || std::isdigit(static_cast<unsigned char>(name[0]))) {
    return false;
  }
  return std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
  });
}

// Throws ModelError for a symbol in e that C has no name for.
void CheckSymbols(const GiNaC::ex& e, const NameMap& names) {
  if (GiNaC::is_a<GiNaC::symbol>(e)) {
    const std::string& name = GiNaC::ex_to<GiNaC::symbol>(e).get_name();
    if (names.count(name) == 0) {
      throw ModelError(fmt::format("cannot generate C: unknown symbol '{}' in the equations",
                                   CText(name)));
    }
  }
  for (std::size_t i = 0; i < e.nops(); ++i) CheckSymbols(e.op(i), names);
}

// The operations of a C expression, counted in its text (so that the count is as stable as
// the text): binary + and −, * and /, and calls.
int Operations(std::string_view c) {
  int ops = 0;
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (c[i] == '*' || c[i] == '/') ++ops;
    if ((c[i] == '+' || c[i] == '-') && i > 0 && c[i - 1] == ' ') ++ops;
    if (c[i] == '(' && i > 0 && std::isalnum(static_cast<unsigned char>(c[i - 1]))) ++ops;
  }
  return ops;
}

using NamedOutputs = std::vector<std::pair<std::string, GiNaC::ex>>;

void AddNamed(NamedOutputs& out, const char* array, const std::vector<GiNaC::ex>& values) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    out.emplace_back(fmt::format("{}[{}]", array, i), values[i]);
  }
}

// The body of one function: `out`'s common subexpressions named as the printed equations name
// theirs (shared.h), in a canonical order and sign so that the text is the same on every run,
// then the assignments. `names` maps the inputs; the counts add to `code`'s.
std::string WriteBody(NamedOutputs out, NameMap names, const std::set<std::string>& reserved,
                 CCode& code) {
  std::vector<GiNaC::ex*> pointers;
  for (auto& [target, value] : out) pointers.push_back(&value);
  const SharedSubexpressions shared = ShareSubexpressions(pointers, "t", reserved);
  std::string body, outputs;
  for (const auto& [symbol, definition] : shared.definitions) {
    const std::string& name = GiNaC::ex_to<GiNaC::symbol>(symbol).get_name();
    CheckSymbols(definition, names);
    const std::string c = PrintExpression(definition, Dialect::kC, names);
    code.operations += Operations(c);
    body += fmt::format("  const double {} = {};\n", name, c);
    names.emplace(name, name);
  }
  for (const auto& [target, value] : out) {
    CheckSymbols(value, names);
    const std::string c = PrintExpression(value, Dialect::kC, names);
    code.operations += Operations(c);
    outputs += fmt::format("  {} = {};\n", target, c);
  }
  code.temporaries += static_cast<int>(shared.definitions.size());
  return body + outputs;
}

}  // namespace

CCode WriteC(const multibody::Model& model, const RhsExpressions& rhs,
             const std::string& model_name, const std::string& function_name) {
  if (!IsCIdentifier(function_name)) {
    throw ModelError(fmt::format("cannot generate C: the function name '{}' is not a C "
                                 "identifier (letters, digits and '_', not starting with a "
                                 "digit)", CText(function_name)));
  }
  const int n = model.num_coordinates();
  const int nz = model.num_extra_states();
  // Every symbol prints by its name through `names` (t, x[k], r[s]); the intermediates (tK)
  // print as their own names, kept apart from the model's names.
  NameMap names{{GiNaC::ex_to<GiNaC::symbol>(rhs.t).get_name(), "t"}};
  std::string inputs;
  const auto bind = [&](const GiNaC::ex& symbol, const std::string& c_name) {
    const std::string& name = GiNaC::ex_to<GiNaC::symbol>(symbol).get_name();
    if (!names.emplace(name, c_name).second) {
      throw ModelError(fmt::format("cannot generate C: two inputs of the model are named '{}'; "
                                   "rename one in the model", CText(name)));
    }
    inputs += fmt::format(" *   {} = {}\n", c_name, CText(name));
  };
  for (std::size_t k = 0; k < rhs.x.size(); ++k) bind(rhs.x[k], fmt::format("x[{}]", k));
  const NameMap state_names = names;  // the constraint rows read t and x only
  for (std::size_t k = 0; k < rhs.r.size(); ++k) bind(rhs.r[k], fmt::format("r[{}]", k));
  std::set<std::string> reserved;
  for (const auto& [name, c_name] : names) reserved.insert(name);

  NamedOutputs rhs_out;
  AddNamed(rhs_out, "M", rhs.M);
  AddNamed(rhs_out, "g", rhs.g);
  AddNamed(rhs_out, "qdot", rhs.qdot);
  AddNamed(rhs_out, "zdot", rhs.zdot);
  CCode code;
  const std::string body = WriteBody(std::move(rhs_out), names, reserved, code);
  // A constrained model's rows of B u + c = 0: a second function of t and x, so the engine's
  // step reads them from here and computes none itself (symbolic_compiled.h).
  const int m = model.num_constraint_rows();
  std::string constraints;
  if (m > 0) {
    NamedOutputs rows;
    AddNamed(rows, "B", rhs.B);
    AddNamed(rows, "velocity", rhs.constraint_velocity);
    AddNamed(rows, "position", rhs.constraint_position);
    AddNamed(rows, "bias", rhs.constraint_bias);
    constraints = fmt::format(
        "\n/* The {1} rows of B u + c = 0 (constraints:): B ({1} x n, column-major), B u + c,\n"
        " * f(q, t) (0 for non-holonomic rows) and the bias Bdot u + cdot. */\n"
        "void {0}_constraints(double t, const double* x, double* B, double* velocity,\n"
        "    double* position, double* bias) {{\n"
        "  (void)t; (void)x; (void)B; (void)velocity; (void)position; (void)bias;\n{2}}}\n",
        function_name, m, WriteBody(std::move(rows), state_names, reserved, code));
  }
  const std::string& f = function_name;
  code.source = fmt::format(
      "/* Generated by hybridtest (`hybridtest equations --format c`, docs/equations.md):\n"
      " * the right-hand side of model '{0}' as the Kane engine computes it, n = {2}\n"
      " * coordinates, {3} restoring-force slots, {4} extra states; {5} common subexpressions,\n"
      " * {6} operations. SI units, as in the model.\n"
      " * Inputs: t [s], x = [q; u; z], r [N]:\n{7}"
      " * Outputs: M (n x n, column-major) and g with M udot = g; qdot = W(q) u; zdot{11}. */\n"
      "#include <math.h>\n\n"
      "const int {1}_n = {2};\n"
      "const int {1}_slots = {3};\n"
      "const int {1}_nz = {4};\n"
      "const int {1}_m = {10};\n"
      "const char {1}_model[] = \"{0}\";\n\n"
      "void {1}(double t, const double* x, const double* r, double* M, double* g, double* qdot,\n"
      "    double* zdot) {{\n"
      "  (void)t; (void)x; (void)r; (void)M; (void)g; (void)qdot; (void)zdot;\n"
      "{8}}}\n{9}",
      CText(model_name), f, n, model.num_slots(), nz, code.temporaries, code.operations, inputs,
      body, constraints, m,
      m > 0 ? fmt::format(";\n * and from {}_constraints the {} constraint rows", f, m) : "");
  return code;
}

}  // namespace hybridtest::symbolic
