// Dimensions of model-file formulas: the rules that follow a dimension through an expression
// tree (expression.h, Dim), used by the parser node by node.
#include <fmt/core.h>

#include <cmath>
#include <cstdlib>
#include <optional>

#include "hybridtest/modelfile/expression.h"
#include "hybridtest/modelfile/units.h"

namespace hybridtest::modelfile {

Dim Dim::OfUnit(std::string_view unit_text) {
  std::string why;
  const std::optional<Unit> unit = unit_text.empty() ? std::nullopt : ParseUnit(unit_text, &why);
  return unit ? FromUnit(unit->dim) : Dim{};
}

std::string DimName(const Dim& d) {
  if (!d.known) return "unknown";
  static constexpr const char* kBase[] = {"kg", "m", "s"};  // written in this order
  static constexpr std::size_t kIndex[] = {1, 0, 2};
  auto power = [](int p) {
    return p == 1 ? std::string() : p == 2 ? std::string("²") : p == 3 ? std::string("³")
                                                                      : fmt::format("^{}", p);
  };
  std::string num, den;
  for (int k = 0; k < 3; ++k) {
    const int p = d.e[kIndex[k]];
    if (p == 0) continue;
    std::string& out = p > 0 ? num : den;
    out += (out.empty() ? "" : "·") + std::string(kBase[k]) + power(std::abs(p));
  }
  if (num.empty()) num.push_back('1');  // (not `= "1"`: GCC 12 warns -Wrestrict there)
  return den.empty() ? num : num + "/" + den;
}

Dim CombineDims(Op op, const Dim& a, const Dim& b, const Dim& c, bool constant_b, double b_value,
                std::string* error) {
  const Dim none;
  constexpr std::array<int, 3> kOne{0, 0, 0};
  auto agree = [&](const Dim& x, const Dim& y, const char* what) {
    if (x.known && y.known && x.e != y.e) {
      *error = fmt::format("{} a quantity in {} and one in {}; units must agree there (check the "
                           "parameters' units)", what, DimName(x), DimName(y));
    }
    return x.known ? x : y;
  };
  auto dimensionless = [&](const Dim& x, const char* what) {
    if (x.known && x.e != kOne) {
      *error = fmt::format("the argument of {} is in {}; it must be dimensionless (divide by a "
                           "reference value)", what, DimName(x));
    }
  };
  switch (op) {
    case Op::kNeg: case Op::kAbs: return a;
    case Op::kAdd: case Op::kSub: return agree(a, b, "adds or subtracts");
    case Op::kMin: case Op::kMax: return agree(a, b, "min() or max() compares");
    case Op::kLt: case Op::kLe: case Op::kGt: case Op::kGe:
      agree(a, b, "the condition compares");
      return Dim::One();
    case Op::kAtan2: agree(a, b, "atan2() takes"); return Dim::One();
    case Op::kIf: return agree(b, c, "the branches of if() give");
    case Op::kMul: case Op::kDiv: {
      if (!a.known || !b.known) return none;
      Dim out = a;
      for (std::size_t k = 0; k < 3; ++k) out.e[k] += (op == Op::kMul ? 1 : -1) * b.e[k];
      return out;
    }
    case Op::kPow: case Op::kSqrt: {
      if (op == Op::kPow) dimensionless(b, "an exponent");
      const bool constant = op == Op::kSqrt || constant_b;
      const double p = op == Op::kSqrt ? 0.5 : b_value;
      if (!a.known || a.e == kOne) return a;
      Dim out = a;
      for (std::size_t k = 0; k < 3; ++k) {
        const double v = p * a.e[k];
        if (!constant || v != std::round(v)) {
          *error = fmt::format("raises a quantity in {} to a power that leaves a fractional or "
                               "variable unit; make the base dimensionless", DimName(a));
          return none;
        }
        out.e[k] = static_cast<int>(v);
      }
      return out;
    }
    case Op::kSin: case Op::kCos: case Op::kTan: case Op::kExp: case Op::kLog:
    case Op::kTanh: case Op::kAsin: case Op::kAcos: case Op::kAtan:
      dimensionless(a, "this function");
      return Dim::One();
    case Op::kSign: return Dim::One();
    default: return none;  // tables: their values carry no unit
  }
}

}  // namespace hybridtest::modelfile
