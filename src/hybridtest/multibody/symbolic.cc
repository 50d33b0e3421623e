// The Symbolic scalar over GiNaC. See symbolic.h.
#include "hybridtest/multibody/symbolic.h"

#include <ginac/ginac.h>

#include <fmt/core.h>

#include <cmath>
#include <string>
#include <map>
#include <mutex>

namespace hybridtest::multibody {

namespace {
std::shared_ptr<const GiNaC::ex> Make(GiNaC::ex e) {
  return std::make_shared<const GiNaC::ex>(std::move(e));
}
const GiNaC::ex& Zero() {
  static const GiNaC::ex zero = 0;
  return zero;
}
}  // namespace

// The rational of v's shortest decimal (0.65 → 13/20): the number as a model file writes it,
// so that GiNaC's arithmetic on it is exact and does not depend on the order it combines terms
// in (float sums do, and GiNaC's order depends on addresses). Non-finite values stay floats.
GiNaC::numeric ExactDecimal(double v) {
  if (!std::isfinite(v)) return GiNaC::numeric(v);
  std::string s = fmt::format("{}", v);  // shortest round-trip: "0.65", "1e-05", "1.57e+20"
  long exponent = 0;
  const auto e = s.find_first_of("eE");
  if (e != std::string::npos) {
    exponent = std::stol(s.substr(e + 1));
    s.resize(e);
  }
  const bool negative = !s.empty() && s[0] == '-';
  if (negative) s.erase(0, 1);
  const auto point = s.find('.');
  if (point != std::string::npos) {
    exponent -= static_cast<long>(s.size() - point - 1);
    s.erase(point, 1);
  }
  GiNaC::numeric mantissa(std::stoll(s));
  if (negative) mantissa = -mantissa;
  const GiNaC::numeric ten(10);
  return exponent >= 0 ? mantissa * ten.power(GiNaC::numeric(exponent))
                       : mantissa / ten.power(GiNaC::numeric(-exponent));
}

Symbolic::Symbolic() = default;
Symbolic::Symbolic(double value) {
  if (value != 0.0) e_ = Make(ExactDecimal(value));
}
Symbolic::Symbolic(const GiNaC::ex& e) {
  if (!e.is_zero()) e_ = Make(e);
}
Symbolic Symbolic::Variable(const std::string& name) {
  return Symbolic(GiNaC::ex(GiNaC::realsymbol(name)));
}
const GiNaC::ex& Symbolic::ex() const { return e_ ? *e_ : Zero(); }

Symbolic& Symbolic::operator+=(const Symbolic& b) { return *this = *this + b; }
Symbolic& Symbolic::operator-=(const Symbolic& b) { return *this = *this - b; }
Symbolic& Symbolic::operator*=(const Symbolic& b) { return *this = *this * b; }
Symbolic& Symbolic::operator/=(const Symbolic& b) { return *this = *this / b; }

Symbolic operator+(const Symbolic& a, const Symbolic& b) { return Symbolic(a.ex() + b.ex()); }
Symbolic operator-(const Symbolic& a, const Symbolic& b) { return Symbolic(a.ex() - b.ex()); }
Symbolic operator*(const Symbolic& a, const Symbolic& b) { return Symbolic(a.ex() * b.ex()); }
Symbolic operator/(const Symbolic& a, const Symbolic& b) { return Symbolic(a.ex() / b.ex()); }
Symbolic operator-(const Symbolic& a) { return Symbolic(-a.ex()); }
Symbolic operator+(const Symbolic& a) { return a; }
bool operator==(const Symbolic& a, const Symbolic& b) { return a.ex().is_equal(b.ex()); }
bool operator!=(const Symbolic& a, const Symbolic& b) { return !(a == b); }

Symbolic sin(const Symbolic& a) { return Symbolic(GiNaC::sin(a.ex())); }
Symbolic cos(const Symbolic& a) { return Symbolic(GiNaC::cos(a.ex())); }
Symbolic tan(const Symbolic& a) { return Symbolic(GiNaC::tan(a.ex())); }
Symbolic exp(const Symbolic& a) { return Symbolic(GiNaC::exp(a.ex())); }
Symbolic log(const Symbolic& a) { return Symbolic(GiNaC::log(a.ex())); }
Symbolic sqrt(const Symbolic& a) { return Symbolic(GiNaC::sqrt(a.ex())); }
Symbolic pow(const Symbolic& a, double p) {
  // Integer and half-integer exponents exactly (x^2, not x^2.0).
  const double twice = 2.0 * p;
  if (twice == static_cast<double>(static_cast<long>(twice)) && std::abs(p) < 1e6) {
    return Symbolic(GiNaC::pow(a.ex(), GiNaC::numeric(static_cast<long>(twice), 2)));
  }
  return Symbolic(GiNaC::pow(a.ex(), GiNaC::numeric(p)));
}
Symbolic pow(const Symbolic& a, const Symbolic& p) { return Symbolic(GiNaC::pow(a.ex(), p.ex())); }
Symbolic atan(const Symbolic& a) { return Symbolic(GiNaC::atan(a.ex())); }
Symbolic asin(const Symbolic& a) { return Symbolic(GiNaC::asin(a.ex())); }
Symbolic acos(const Symbolic& a) { return Symbolic(GiNaC::acos(a.ex())); }
Symbolic tanh(const Symbolic& a) { return Symbolic(GiNaC::tanh(a.ex())); }
Symbolic atan2(const Symbolic& y, const Symbolic& x) {
  return Symbolic(GiNaC::atan2(y.ex(), x.ex()));
}
Symbolic abs(const Symbolic& a) { return Symbolic(GiNaC::abs(a.ex())); }
Symbolic sign(const Symbolic& a) { return Symbolic(GiNaC::csgn(a.ex())); }

Symbolic ApplyFunction(const std::string& name, const Symbolic& a) {
  // GiNaC functions are registered once per name, process-wide.
  static std::mutex mutex;
  static std::map<std::string, unsigned> serials;
  unsigned serial = 0;
  {
    const std::lock_guard<std::mutex> lock(mutex);
    auto it = serials.find(name);
    if (it == serials.end()) {
      it = serials.emplace(name, GiNaC::function::register_new(
                                     GiNaC::function_options(name, 1)))
               .first;
    }
    serial = it->second;
  }
  return Symbolic(GiNaC::function(serial, a.ex()));
}

}  // namespace hybridtest::multibody
