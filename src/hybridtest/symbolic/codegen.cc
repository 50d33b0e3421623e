// C code with common subexpressions eliminated. See codegen.h.
#include "hybridtest/symbolic/codegen.h"

#include <fmt/core.h>
#include <ginac/ginac.h>

#include <algorithm>
#include <cctype>
#include <map>
#include <string_view>
#include <vector>

#include "hybridtest/common/error.h"

namespace hybridtest::symbolic {

namespace {

// A double literal that C reads back exactly (17 significant digits), always with a point or
// an exponent so that C never takes it for an int.
std::string Literal(const GiNaC::numeric& n) {
  if (!n.is_real()) {
    throw ModelError("cannot generate C: the model's equations contain a complex number");
  }
  const double v = n.to_double();
  std::string s = fmt::format("{:.17g}", v);
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return v < 0 ? "(" + s + ")" : s;
}

// The functions of the Symbolic scalar that C's <math.h> computes, by GiNaC's name.
std::string CFunction(const std::string& name) {
  static const std::map<std::string, std::string> kNames = {
      {"sin", "sin"},   {"cos", "cos"},   {"tan", "tan"},     {"exp", "exp"},
      {"log", "log"},   {"atan", "atan"}, {"asin", "asin"},   {"acos", "acos"},
      {"tanh", "tanh"}, {"abs", "fabs"},  {"atan2", "atan2"}, {"csgn", ""}};
  const auto it = kNames.find(name);
  if (it == kNames.end()) {
    throw ModelError(fmt::format(
        "cannot generate C: the equations call '{}', which is not a C function (a model file's "
        "1-D table is printed as a function of its argument but has no C form); replace the "
        "table by a formula, or run the model without `compiled: true`", name));
  }
  return it->second;
}

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

class Emitter {
 public:
  void Bind(const GiNaC::ex& symbol, std::string c_name) { names_[symbol] = std::move(c_name); }

  // A C atom for e: a variable, an input, or a literal; emits e's temporary (and those of its
  // subexpressions) first if e is new.
  std::string Atom(const GiNaC::ex& e) {
    if (GiNaC::is_a<GiNaC::numeric>(e)) return Literal(GiNaC::ex_to<GiNaC::numeric>(e));
    const auto it = names_.find(e);
    if (it != names_.end()) return it->second;
    if (GiNaC::is_a<GiNaC::symbol>(e)) {
      throw ModelError(fmt::format("cannot generate C: unknown symbol '{}' in the equations",
                                   GiNaC::ex_to<GiNaC::symbol>(e).get_name()));
    }
    const std::string value = Expression(e);
    const std::string name = fmt::format("t{}", temporaries_++);
    body_ += fmt::format("  const double {} = {};\n", name, value);
    names_.emplace(e, name);
    return name;
  }

  const std::string& body() const { return body_; }
  int temporaries() const { return temporaries_; }
  int operations() const { return operations_; }

 private:
  // b^k for a whole k ≥ 1: products up to k = 4, pow beyond.
  std::string WholePower(const GiNaC::ex& base, long k) {
    const std::string b = Atom(base);
    if (k == 1) return b;
    ++operations_;
    if (k > 4) return fmt::format("pow({}, {}.0)", b, k);
    operations_ += static_cast<int>(k) - 2;
    std::string s = b;
    for (long i = 1; i < k; ++i) s += " * " + b;
    return s;
  }

  // base^p for a positive exponent p (whole, half or other).
  std::string PositivePower(const GiNaC::ex& base, const GiNaC::numeric& p) {
    if (p.is_integer()) return WholePower(base, p.to_long());
    ++operations_;
    if (p == GiNaC::numeric(1, 2)) return fmt::format("sqrt({})", Atom(base));
    return fmt::format("pow({}, {})", Atom(base), Literal(p));
  }

  std::string Expression(const GiNaC::ex& e) {
    if (GiNaC::is_a<GiNaC::add>(e)) {
      std::string s;
      for (std::size_t i = 0; i < e.nops(); ++i) s += (i == 0 ? "" : " + ") + Atom(e.op(i));
      operations_ += static_cast<int>(e.nops()) - 1;
      return s;
    }
    if (GiNaC::is_a<GiNaC::mul>(e)) {
      std::vector<std::string> numerator, denominator;
      for (std::size_t i = 0; i < e.nops(); ++i) {
        const GiNaC::ex& f = e.op(i);
        if (GiNaC::is_a<GiNaC::power>(f) && GiNaC::is_a<GiNaC::numeric>(f.op(1)) &&
            GiNaC::ex_to<GiNaC::numeric>(f.op(1)).is_negative()) {
          denominator.push_back(Atom(GiNaC::pow(f.op(0), -f.op(1))));
        } else {
          numerator.push_back(Atom(f));
        }
      }
      std::string s;
      for (const std::string& f : numerator) s += (s.empty() ? "" : " * ") + f;
      if (s.empty()) s = "1.0";
      operations_ += static_cast<int>(numerator.size() + denominator.size()) - 1;
      if (denominator.empty()) return s;
      std::string d;
      for (const std::string& f : denominator) d += (d.empty() ? "" : " * ") + f;
      return denominator.size() == 1 ? fmt::format("{} / {}", s, d)
                                     : fmt::format("{} / ({})", s, d);
    }
    if (GiNaC::is_a<GiNaC::power>(e)) {
      const GiNaC::ex& exponent = e.op(1);
      if (!GiNaC::is_a<GiNaC::numeric>(exponent)) {
        ++operations_;
        return fmt::format("pow({}, {})", Atom(e.op(0)), Atom(exponent));
      }
      const GiNaC::numeric p = GiNaC::ex_to<GiNaC::numeric>(exponent);
      if (!p.is_negative()) return PositivePower(e.op(0), p);
      ++operations_;
      return fmt::format("1.0 / {}", Atom(GiNaC::pow(e.op(0), -exponent)));
    }
    if (GiNaC::is_a<GiNaC::function>(e)) {
      const std::string c = CFunction(GiNaC::ex_to<GiNaC::function>(e).get_name());
      ++operations_;
      if (c.empty()) {  // csgn: the sign of a real, 0 at 0
        const std::string a = Atom(e.op(0));
        return fmt::format("(double)(({} > 0.0) - ({} < 0.0))", a, a);
      }
      std::string args;
      for (std::size_t i = 0; i < e.nops(); ++i) args += (i == 0 ? "" : ", ") + Atom(e.op(i));
      return fmt::format("{}({})", c, args);
    }
    throw ModelError(fmt::format("cannot generate C for the expression {} (an unexpected kind)",
                                 GiNaC::ex_to<GiNaC::basic>(e).class_name()));
  }

  std::map<GiNaC::ex, std::string, GiNaC::ex_is_less> names_;
  std::string body_;
  int temporaries_ = 0;
  int operations_ = 0;
};

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
  Emitter emit;
  emit.Bind(rhs.t, "t");
  std::string inputs;
  for (std::size_t k = 0; k < rhs.x.size(); ++k) {
    emit.Bind(rhs.x[k], fmt::format("x[{}]", k));
    inputs += fmt::format(" *   x[{}] = {}\n", k, CText(GiNaC::ex_to<GiNaC::symbol>(rhs.x[k]).get_name()));
  }
  for (std::size_t k = 0; k < rhs.r.size(); ++k) {
    emit.Bind(rhs.r[k], fmt::format("r[{}]", k));
    inputs += fmt::format(" *   r[{}] = {}\n", k, CText(GiNaC::ex_to<GiNaC::symbol>(rhs.r[k]).get_name()));
  }
  std::string outputs;
  auto assign = [&](const char* array, const std::vector<GiNaC::ex>& values) {
    for (std::size_t i = 0; i < values.size(); ++i) {
      outputs += fmt::format("  {}[{}] = {};\n", array, i, emit.Atom(values[i]));
    }
  };
  assign("M", rhs.M);
  assign("g", rhs.g);
  assign("qdot", rhs.qdot);
  assign("zdot", rhs.zdot);

  CCode code;
  code.temporaries = emit.temporaries();
  code.operations = emit.operations();
  const std::string& f = function_name;
  code.source = fmt::format(
      "/* Generated by hybridtest (`hybridtest equations --format c`, docs/equations.md):\n"
      " * the right-hand side of model '{0}' as the Kane engine computes it, n = {2}\n"
      " * coordinates, {3} restoring-force slots, {4} extra states; {5} common subexpressions,\n"
      " * {6} operations. SI units, as in the model.\n"
      " * Inputs: t [s], x = [q; u; z], r [N]:\n{7}"
      " * Outputs: M (n x n, column-major) and g with M udot = g; qdot = W(q) u; zdot. */\n"
      "#include <math.h>\n\n"
      "const int {1}_n = {2};\n"
      "const int {1}_slots = {3};\n"
      "const int {1}_nz = {4};\n"
      "const char {1}_model[] = \"{0}\";\n\n"
      "void {1}(double t, const double* x, const double* r, double* M, double* g, double* qdot,\n"
      "    double* zdot) {{\n"
      "  (void)t; (void)x; (void)r; (void)M; (void)g; (void)qdot; (void)zdot;\n"
      "{8}{9}}}\n",
      CText(model_name), f, n, model.num_slots(), nz, code.temporaries, code.operations, inputs,
      emit.body(), outputs);
  return code;
}

}  // namespace hybridtest::symbolic
