// The C dialect's literals, calls and powers. See print_c.h.
#include "hybridtest/symbolic/print_c.h"

#include <fmt/core.h>

#include <map>

#include "hybridtest/common/error.h"

namespace hybridtest::symbolic::c_print {

std::string Literal(const GiNaC::numeric& n) {
  if (!n.is_real()) {
    throw ModelError("cannot generate C: the model's equations contain a complex number");
  }
  std::string s = fmt::format("{:.17g}", n.to_double());
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

std::string Call(const std::string& name, const std::string& arguments) {
  // GiNaC's name → <math.h>'s ("" for csgn, which C lacks and is written out).
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
  if (!it->second.empty()) return fmt::format("{}({})", it->second, arguments);
  // csgn: the sign of a real, 0 at 0.
  return fmt::format("(double)(({0} > 0.0) - ({0} < 0.0))", arguments);
}

std::string Power(const std::string& base, const std::string& wrapped_base,
                  const GiNaC::ex& exponent, const std::string& exponent_text, bool* is_product) {
  const GiNaC::numeric* k = GiNaC::is_a<GiNaC::numeric>(exponent)
                                ? &GiNaC::ex_to<GiNaC::numeric>(exponent) : nullptr;
  if (k == nullptr || !k->is_pos_integer() || k->to_long() > 4) {
    *is_product = false;
    return "pow(" + base + ", " + exponent_text + ")";
  }
  std::string s = wrapped_base;
  for (long i = 1; i < k->to_long(); ++i) s += "*" + wrapped_base;
  *is_product = true;
  return s;
}

}  // namespace hybridtest::symbolic::c_print
