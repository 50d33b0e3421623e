// Expressions as Markdown text, LaTeX, SymPy or C (C's own parts in print_c.cc). See
// print_expression.h.
#include "hybridtest/symbolic/print_expression.h"

#include <fmt/core.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>
#include <string_view>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/symbolic/print_c.h"
#include "hybridtest/symbolic/print_numbers.h"

namespace hybridtest::symbolic {

namespace {

// Term texts in a fixed order (their text without a leading minus, then the text): GiNaC's
// own order depends on addresses and changes between processes.
void SortTexts(std::vector<std::string>& texts) {
  const auto key = [](const std::string& t) {
    return std::string_view(t).substr(!t.empty() && t[0] == '-' ? 1 : 0);
  };
  std::sort(texts.begin(), texts.end(), [&](const std::string& a, const std::string& b) {
    const auto ka = key(a), kb = key(b);
    return ka != kb ? ka < kb : a < b;
  });
}

// x^k with k a negative number: printed as 1/x^(−k).
bool IsReciprocal(const GiNaC::ex& e) {
  return GiNaC::is_a<GiNaC::power>(e) && GiNaC::is_a<GiNaC::numeric>(e.op(1)) &&
         GiNaC::ex_to<GiNaC::numeric>(e.op(1)).is_negative();
}

std::string AbsText(const GiNaC::numeric& n) {
  std::ostringstream os;
  os << abs(n);
  return os.str();
}

// A printed term negated: "-x*y" ↔ "x*y" (every negative term prints with a leading '-').
std::string Negated(const std::string& term) {
  return !term.empty() && term[0] == '-' ? term.substr(1) : "-" + term;
}

// Binding strength of what an expression prints as: a sum binds weakest.
enum Precedence { kSum = 1, kProduct = 2, kPower = 3, kAtom = 4 };

struct Printed {
  std::string text;
  int precedence;
};

class Printer {
 public:
  Printer(Dialect d, const NameMap& names) : d_(d), names_(names) {}

  std::string Wrap(const Printed& p, int needed) const {
    if (p.precedence >= needed) return p.text;
    return d_ == Dialect::kLatex ? "\\left(" + p.text + "\\right)" : "(" + p.text + ")";
  }

  Printed Number(const GiNaC::numeric& n) const {
    if (d_ == Dialect::kC) return {c_print::Literal(n), n.is_negative() ? kSum : kAtom};
    if (const auto exact = number_text::ShortExactForm(n)) {
      if (exact->root == 1) return Number(exact->factor);
      return Print(GiNaC::ex(exact->factor) * GiNaC::sqrt(GiNaC::ex(exact->root)));
    }
    if (n.is_integer()) {
      std::ostringstream os;
      os << n;
      return {os.str(), n.is_negative() ? kSum : kAtom};
    }
    if (number_text::AsFraction(n)) {
      std::ostringstream num, den;
      num << n.numer();
      den << n.denom();
      switch (d_) {
        // A negative fraction with its sign in front, as every negative term: a sum's sign
        // is read off its first term's text (CanonicalSign).
        case Dialect::kLatex:
          return {fmt::format("{}\\frac{{{}}}{{{}}}", n.is_negative() ? "-" : "",
                              AbsText(n.numer()),
                              den.str()), n.is_negative() ? kSum : kAtom};
        case Dialect::kSympy:
          return {fmt::format("{}sp.Rational({}, {})", n.is_negative() ? "-" : "",
                              AbsText(n.numer()), den.str()), n.is_negative() ? kSum : kAtom};
        default:
          return {num.str() + "/" + den.str(), kSum};
      }
    }
    std::string s =
        n.is_rational() ? number_text::Decimal(n) : number_text::ShortDecimal(n.to_double());
    if (d_ == Dialect::kLatex) {
      const auto e = s.find('e');
      if (e != std::string::npos) {
        const std::string exponent = s.substr(e + 1);
        s = fmt::format("{} \\cdot 10^{{{}}}", s.substr(0, e),
                        exponent[0] == '+' ? exponent.substr(1) : exponent);
      }
    }
    return {s, n.is_negative() ? kSum : kAtom};
  }

  Printed Symbol(const GiNaC::symbol& s) const {
    const auto it = names_.find(s.get_name());
    if (it != names_.end()) return {it->second, kAtom};
    // Not in the map: still printed safely in its dialect.
    switch (d_) {
      case Dialect::kSympy: return {PythonName(s.get_name()), kAtom};
      case Dialect::kLatex: return {LatexName(s.get_name()), kAtom};
      default: return {s.get_name(), kAtom};
    }
  }

  Printed Function(const GiNaC::ex& e) const {
    const std::string name = GiNaC::ex_to<GiNaC::function>(e).get_name();
    std::vector<std::string> args;
    for (std::size_t i = 0; i < e.nops(); ++i) args.push_back(Print(e.op(i)).text);
    std::string joined;
    for (std::size_t i = 0; i < args.size(); ++i) joined += (i ? ", " : "") + args[i];
    static const std::set<std::string> kKnown = {"sin", "cos", "tan", "exp", "log", "atan",
                                                 "asin", "acos", "tanh", "atan2"};
    switch (d_) {
      case Dialect::kC: return {c_print::Call(name, joined), kAtom};
      case Dialect::kSympy:
        if (kKnown.count(name)) return {fmt::format("sp.{}({})", name, joined), kAtom};
        if (name == "abs") return {fmt::format("sp.Abs({})", joined), kAtom};
        if (name == "csgn") return {fmt::format("sp.sign({})", joined), kAtom};
        return {fmt::format("sp.Function({})({})", PythonString(name), joined), kAtom};
      case Dialect::kLatex:
        if (name == "abs") return {fmt::format("\\left|{}\\right|", joined), kAtom};
        if (name == "sin" || name == "cos" || name == "tan" || name == "exp" || name == "log" ||
            name == "tanh") {
          return {fmt::format("\\{}{{\\left({}\\right)}}", name, joined), kAtom};
        }
        return {fmt::format("\\operatorname{{{}}}{{\\left({}\\right)}}",
                            name == "csgn" ? "sgn" : LatexText(name), joined), kAtom};
      default:
        return {fmt::format("{}({})", name == "csgn" ? "sign" : name, joined), kAtom};
    }
  }

  // base^exponent with the base printed as b.
  Printed Power(const Printed& b, const GiNaC::ex& exponent) const {
    if (exponent.is_equal(GiNaC::numeric(1, 2))) {
      switch (d_) {
        case Dialect::kLatex: return {"\\sqrt{" + b.text + "}", kAtom};
        case Dialect::kSympy: return {"sp.sqrt(" + b.text + ")", kAtom};
        default: return {"sqrt(" + b.text + ")", kAtom};
      }
    }
    const Printed x = Print(exponent);
    if (d_ == Dialect::kC) {
      bool product = false;
      std::string s = c_print::Power(b.text, Wrap(b, kAtom), exponent, x.text, &product);
      return {std::move(s), product ? kProduct : kAtom};
    }
    switch (d_) {
      case Dialect::kLatex: return {Wrap(b, kAtom) + "^{" + x.text + "}", kPower};
      case Dialect::kSympy: return {Wrap(b, kAtom) + "**" + Wrap(x, kAtom), kPower};
      default: return {Wrap(b, kAtom) + "^" + Wrap(x, kAtom), kPower};
    }
  }

  // A sum, or a whole power of one, in its canonical sign (Sum); *negate toggles when the
  // text is of −f (a flipped sum, or an odd power of one). Anything else as Print does.
  Printed SignedFactor(const GiNaC::ex& f, bool* negate) const {
    bool flipped = false;
    if (GiNaC::is_a<GiNaC::add>(f)) {
      const Printed p = Sum(f, &flipped);
      if (flipped) *negate = !*negate;
      return p;
    }
    if (GiNaC::is_a<GiNaC::power>(f) && GiNaC::is_a<GiNaC::add>(f.op(0)) &&
        GiNaC::is_a<GiNaC::numeric>(f.op(1)) &&
        GiNaC::ex_to<GiNaC::numeric>(f.op(1)).is_pos_integer()) {
      const Printed base = Sum(f.op(0), &flipped);
      if (flipped && GiNaC::ex_to<GiNaC::numeric>(f.op(1)).is_odd()) *negate = !*negate;
      return Power(base, f.op(1));
    }
    if (GiNaC::is_a<GiNaC::power>(f) && !IsReciprocal(f)) return Power(Print(f.op(0)), f.op(1));
    return Print(f);
  }

  // A product: numeric coefficient, numerator factors, denominator factors.
  Printed Product(const GiNaC::ex& e) const {
    GiNaC::numeric coefficient = 1;
    std::vector<GiNaC::ex> top, bottom;
    for (std::size_t i = 0; i < e.nops(); ++i) {
      const GiNaC::ex f = e.op(i);
      if (GiNaC::is_a<GiNaC::numeric>(f)) {
        coefficient *= GiNaC::ex_to<GiNaC::numeric>(f);
      } else if (GiNaC::is_a<GiNaC::power>(f) && GiNaC::is_a<GiNaC::numeric>(f.op(1)) &&
                 GiNaC::ex_to<GiNaC::numeric>(f.op(1)).is_negative()) {
        bottom.push_back(GiNaC::pow(f.op(0), -f.op(1)));
      } else {
        top.push_back(f);
      }
    }
    if (d_ != Dialect::kC) {
      if (const auto exact = number_text::ShortExactForm(coefficient)) {
        // r·√k: r the coefficient, √k a factor (printed in the dialect's sqrt).
        coefficient = exact->factor;
        if (exact->root != 1) top.push_back(GiNaC::sqrt(GiNaC::ex(exact->root)));
      }
    }
    bool negative = coefficient.is_negative();
    if (negative) coefficient = -coefficient;
    // A factor in front (not vector::insert at begin(): GCC 12 warns -Wnull-dereference
    // inside GiNaC's ptr there).
    const auto prepend = [](std::vector<GiNaC::ex>& factors, const GiNaC::ex& first) {
      std::vector<GiNaC::ex> out;
      out.reserve(factors.size() + 1);
      out.push_back(first);
      for (const GiNaC::ex& f : factors) out.push_back(f);
      factors.swap(out);
    };
    if (d_ != Dialect::kC && number_text::AsFraction(coefficient)) {
      if (!coefficient.numer().is_equal(1) || top.empty()) prepend(top, coefficient.numer());
      prepend(bottom, coefficient.denom());
    } else if (!coefficient.is_equal(1) || top.empty()) {
      prepend(top, coefficient);
    }
    const std::string times = d_ == Dialect::kLatex ? " " : "*";
    // The coefficient (if any) first, the other factors in a fixed order.
    auto join = [&](const std::vector<GiNaC::ex>& factors, int needed) {
      std::vector<std::string> texts;
      std::size_t fixed = 0;
      for (const GiNaC::ex& f : factors) {
        texts.push_back(Wrap(SignedFactor(f, &negative), needed));
        if (GiNaC::is_a<GiNaC::numeric>(f) && texts.size() == 1) fixed = 1;
      }
      std::vector<std::string> rest(texts.begin() + static_cast<std::ptrdiff_t>(fixed), texts.end());
      SortTexts(rest);
      std::string s = fixed ? texts[0] : "";
      for (const std::string& t : rest) s += (s.empty() ? "" : times) + t;
      return s;
    };
    std::string text;
    if (bottom.empty()) {
      text = join(top, kProduct);
    } else if (d_ == Dialect::kLatex) {
      text = "\\frac{" + join(top, kProduct) + "}{" + join(bottom, kProduct) + "}";
    } else {
      const std::string den = join(bottom, kPower);
      text = join(top, kProduct) + "/" + (bottom.size() > 1 ? "(" + den + ")" : den);
    }
    return {negative ? "-" + text : text, negative ? kSum : kProduct};
  }

  std::vector<std::string> Terms(const GiNaC::ex& e) const {
    std::vector<std::string> terms;
    for (std::size_t i = 0; i < e.nops(); ++i) terms.push_back(Print(e.op(i)).text);
    SortTexts(terms);
    return terms;
  }

  // A sum, or with `flipped` its canonical sign: the one whose first term (in the printed
  // order) is positive, *flipped telling whether the text is of −e. GiNaC's mul::eval writes a
  // sum that is a factor as (x − a) in one process and (a − x) in another (its sign follows
  // an address-dependent term order); printed canonically, both are the same text.
  Printed Sum(const GiNaC::ex& e, bool* flipped = nullptr) const {
    std::string text;
    std::vector<std::string> terms = Terms(e);
    if (flipped != nullptr) {
      *flipped = !terms.empty() && !terms[0].empty() && terms[0][0] == '-';
      if (*flipped) {
        for (std::string& t : terms) t = Negated(t);
      }
    }
    for (std::size_t i = 0; i < terms.size(); ++i) {
      const std::string& t = terms[i];
      if (i == 0) {
        text = t;
      } else if (!t.empty() && t[0] == '-') {
        text += " - " + t.substr(1);
      } else {
        text += " + " + t;
      }
    }
    return {text, kSum};
  }

  Printed Print(const GiNaC::ex& e) const {
    if (GiNaC::is_a<GiNaC::numeric>(e)) return Number(GiNaC::ex_to<GiNaC::numeric>(e));
    if (GiNaC::is_a<GiNaC::symbol>(e)) return Symbol(GiNaC::ex_to<GiNaC::symbol>(e));
    if (GiNaC::is_a<GiNaC::add>(e)) return Sum(e);
    if (GiNaC::is_a<GiNaC::mul>(e)) return Product(e);
    if (GiNaC::is_a<GiNaC::power>(e)) {
      if (IsReciprocal(e)) {
        // 1/x^k: GiNaC evaluates mul(1, e) back to the power itself, whose operands are
        // not factors (printing it as a product made x^(-1) print as -x).
        bool negative = false;
        const Printed b = SignedFactor(GiNaC::pow(e.op(0), -e.op(1)), &negative);
        const std::string sign = negative ? "-" : "";
        if (d_ == Dialect::kLatex) return {sign + "\\frac{1}{" + b.text + "}", negative ? kSum : kAtom};
        const char* one = d_ == Dialect::kC ? "1.0/" : "1/";
        return {sign + one + Wrap(b, kPower), negative ? kSum : kProduct};
      }
      bool negative = false;
      const Printed p = SignedFactor(e, &negative);
      if (negative) return {"-" + p.text, kSum};
      return p;
    }
    if (GiNaC::is_a<GiNaC::function>(e)) return Function(e);
    if (GiNaC::is_a<GiNaC::constant>(e)) {
      if (d_ == Dialect::kC) return Number(GiNaC::ex_to<GiNaC::numeric>(e.evalf()));
      std::ostringstream os;
      os << e;
      const std::string s = os.str();
      if (s == "Pi") return {d_ == Dialect::kSympy ? "sp.pi" : d_ == Dialect::kLatex ? "\\pi" : "pi", kAtom};
      return {s, kAtom};
    }
    std::ostringstream os;
    os << e;
    return {os.str(), kAtom};
  }

 private:
  Dialect d_;
  const NameMap& names_;
};

}  // namespace

std::string PrintExpression(const GiNaC::ex& e, Dialect dialect, const NameMap& names) {
  return Printer(dialect, names).Print(e).text;
}

std::vector<std::string> PrintTerms(const GiNaC::ex& e, Dialect dialect, const NameMap& names) {
  const Printer printer(dialect, names);
  if (!GiNaC::is_a<GiNaC::add>(e)) return {printer.Print(e).text};
  return printer.Terms(e);
}

}  // namespace hybridtest::symbolic
