// Simplification for printing. See simplify.h.
#include "hybridtest/symbolic/simplify.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace hybridtest::symbolic {

namespace {

constexpr double kDyadicScale = 1024.0;  // exact fractions with denominators up to 2^10
constexpr double kChop = 1e-13;          // relative size of a rounding term

// A float that is (within `tolerance`, relative) a dyadic fraction k/1024, as that exact
// rational; otherwise the float itself.
GiNaC::ex ExactIfDyadic(const GiNaC::numeric& n, double tolerance) {
  if (!n.is_real() || n.is_rational()) return n;
  const double x = n.to_double();
  const double scaled = x * kDyadicScale;
  const double k = std::round(scaled);
  if (std::abs(k) > 9.0e15) return n;
  if (std::abs(scaled - k) <= tolerance * std::max(1.0, std::abs(scaled))) {
    return GiNaC::numeric(static_cast<long>(k), static_cast<long>(kDyadicScale));
  }
  return n;
}

struct Exactify : GiNaC::map_function {
  double tolerance;
  explicit Exactify(double tol) : tolerance(tol) {}
  GiNaC::ex operator()(const GiNaC::ex& e) override {
    if (GiNaC::is_a<GiNaC::numeric>(e)) return ExactIfDyadic(GiNaC::ex_to<GiNaC::numeric>(e), tolerance);
    return e.map(*this);
  }
};

// The numeric factor of a term of a sum (1 for a term without one).
double Coefficient(const GiNaC::ex& term) {
  if (GiNaC::is_a<GiNaC::numeric>(term)) return std::abs(GiNaC::ex_to<GiNaC::numeric>(term).to_double());
  if (GiNaC::is_a<GiNaC::mul>(term)) {
    double c = 1.0;
    for (std::size_t i = 0; i < term.nops(); ++i) {
      if (GiNaC::is_a<GiNaC::numeric>(term.op(i))) {
        c *= std::abs(GiNaC::ex_to<GiNaC::numeric>(term.op(i)).to_double());
      }
    }
    return c;
  }
  return 1.0;
}

// Whether e holds a number that is not exact (a float). The engine's numbers are exact
// rationals (multibody/symbolic.h), so usually none: Exactify's walk, which rebuilds every
// node, is then skipped.
bool HasFloat(const GiNaC::ex& e) {
  if (GiNaC::is_a<GiNaC::numeric>(e)) return !GiNaC::ex_to<GiNaC::numeric>(e).is_rational();
  for (std::size_t i = 0; i < e.nops(); ++i) {
    if (HasFloat(e.op(i))) return true;
  }
  return false;
}

GiNaC::ex ExactIfFloat(const GiNaC::ex& e, double tolerance) {
  if (!HasFloat(e)) return e;
  Exactify exact(tolerance);
  return exact(e);
}

// Drops rounding terms from a sum (recursively inside function arguments). Returns e itself
// (not a rebuilt copy, so that GiNaC keeps knowing it is expanded) where nothing is dropped.
GiNaC::ex Chop(const GiNaC::ex& e) {  // NOLINT(misc-no-recursion)
  if (e.nops() == 0) return e;
  bool changed = false;
  std::vector<GiNaC::ex> ops;
  ops.reserve(e.nops());
  double largest = 0.0;
  const bool sum = GiNaC::is_a<GiNaC::add>(e);
  for (std::size_t i = 0; sum && i < e.nops(); ++i) largest = std::max(largest, Coefficient(e.op(i)));
  for (std::size_t i = 0; i < e.nops(); ++i) {
    if (sum && Coefficient(e.op(i)) < kChop * largest) {
      changed = true;
      continue;
    }
    ops.push_back(Chop(e.op(i)));
    changed = changed || !GiNaC::are_ex_trivially_equal(ops.back(), e.op(i));
  }
  if (!changed) return e;
  if (sum) {
    GiNaC::ex s = 0;
    for (const GiNaC::ex& op : ops) s += op;
    return s;
  }
  struct Children : GiNaC::map_function {
    GiNaC::ex operator()(const GiNaC::ex& x) override { return Chop(x); }
  } children;
  return e.map(children);
}

bool IsSinPower(const GiNaC::ex& e) {
  return GiNaC::is_a<GiNaC::power>(e) && GiNaC::is_the_function<GiNaC::sin_SERIAL>(e.op(0)) &&
         e.op(1).info(GiNaC::info_flags::posint) && GiNaC::ex_to<GiNaC::numeric>(e.op(1)).to_int() >= 2;
}

bool HasSinPower(const GiNaC::ex& e) {  // NOLINT(misc-no-recursion)
  if (IsSinPower(e)) return true;
  for (std::size_t i = 0; i < e.nops(); ++i) {
    if (HasSinPower(e.op(i))) return true;
  }
  return false;
}

// Step 3's substitution: every sin(a)^n, n a whole number ≥ 2, becomes
// sin(a)^(n mod 2)·(1 − cos(a)²)^(n div 2), inside function arguments too (what GiNaC's
// algebraic subs of sin(x)² = 1 − cos(x)² does, without its pattern matching at every node).
struct SinSquares : GiNaC::map_function {
  GiNaC::ex operator()(const GiNaC::ex& e) override {  // NOLINT(misc-no-recursion)
    if (IsSinPower(e)) {
      const int n = GiNaC::ex_to<GiNaC::numeric>(e.op(1)).to_int();
      const GiNaC::ex a = (*this)(e.op(0).op(0));
      return GiNaC::pow(GiNaC::sin(a), n % 2) * GiNaC::pow(1 - GiNaC::pow(GiNaC::cos(a), 2), n / 2);
    }
    // Untouched (and so still known to be expanded) where there is nothing to replace: GiNaC
    // rebuilds a sum or product that it maps, changed or not.
    if (e.nops() == 0 || !HasSinPower(e)) return e;
    return e.map(*this);
  }
};

}  // namespace

GiNaC::ex ExactDyadic(const GiNaC::numeric& n) { return ExactIfDyadic(n, 0.0); }

GiNaC::ex Simplify(const GiNaC::ex& e) { return Simplifier()(e); }

// Steps 1 and 2 bottom-up, once per subexpression object: its children exact and expanded,
// then itself expanded (which then only distributes its own products over its children's
// sums, as GiNaC's expand does after expanding the children).
GiNaC::ex Simplifier::Expanded(const GiNaC::ex& e) {  // NOLINT(misc-no-recursion)
  if (GiNaC::is_a<GiNaC::numeric>(e)) return ExactIfDyadic(GiNaC::ex_to<GiNaC::numeric>(e), 0.0);
  if (e.nops() == 0) return e;
  const GiNaC::basic* key = &GiNaC::ex_to<GiNaC::basic>(e);
  const auto found = expanded_.find(key);
  if (found != expanded_.end()) return found->second.second;
  struct Children : GiNaC::map_function {
    Simplifier* self;
    explicit Children(Simplifier* s) : self(s) {}
    GiNaC::ex operator()(const GiNaC::ex& x) override { return self->Expanded(x); }
  } children(this);
  GiNaC::ex result = e.map(children).expand();
  expanded_.emplace(key, std::pair{e, result});
  return result;
}

GiNaC::ex Simplifier::operator()(const GiNaC::ex& e) {
  SinSquares pythagoras;
  const GiNaC::ex s = pythagoras(Expanded(e)).expand();
  return ExactIfFloat(Chop(s), kChop).expand();
}

}  // namespace hybridtest::symbolic
