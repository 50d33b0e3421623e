// Numbers as the printers write them. See print_numbers.h.
#include "hybridtest/symbolic/print_numbers.h"

#include <fmt/core.h>

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string_view>

#include "hybridtest/multibody/symbolic.h"

namespace hybridtest::symbolic::number_text {
namespace {

// Significant digits of a decimal's text ("-0.0625" → 3, "1.5e-07" → 2).
int SignificantDigits(std::string_view text) {
  int count = 0;
  bool leading = true;
  for (const char c : text.substr(0, text.find('e'))) {
    if (c < '0' || c > '9' || (leading && c == '0')) continue;
    leading = false;
    ++count;
  }
  return count;
}

// The significant digits of a rational's finite decimal expansion (9.81 → 3), or 99 if it
// has none within 40 places (2/3, and the exact rational of a double such as sin(2π/3)'s).
int FiniteDecimalDigits(const GiNaC::numeric& n) {
  GiNaC::numeric scaled = n;
  for (int k = 0; k < 40 && !scaled.is_integer(); ++k) scaled *= 10;
  if (!scaled.is_integer()) return 99;
  std::ostringstream os;
  os << abs(scaled);
  const std::string digits = os.str();
  const std::size_t first = digits.find_first_not_of('0');
  const std::size_t last = digits.find_last_not_of('0');
  return first == std::string::npos ? 0 : static_cast<int>(last - first + 1);
}

}  // namespace

// The shortest decimal within 1e-15 (relative, a few units in the last place) of v: a number
// as the model file wrote it (1.57, 9.6236), not the last bits of the arithmetic that computed
// it (1.5699999999999998, 9.623599999999996: g m_b cos(2π/3) in doubles). At most 15
// significant digits.
std::string ShortDecimal(double v) {
  if (!std::isfinite(v) || v == 0.0) return fmt::format("{}", v);
  for (int digits = 1; digits < 15; ++digits) {
    const double w = std::strtod(fmt::format("{:.{}g}", v, digits).c_str(), nullptr);
    if (std::abs(w - v) <= 1e-15 * std::abs(v)) return fmt::format("{}", w);
  }
  return fmt::format("{}", std::strtod(fmt::format("{:.15g}", v).c_str(), nullptr));
}

// The exact number a floating-point coefficient (a float, or the exact rational of a double:
// no short decimal, no small fraction) stands for, if it is a short one: a whole
// number (−1.0000000000000002 → −1) or a decimal of at most 6 significant digits times √k
// for a small square-free k (g m_b sin(2π/3) = 16.668564151719… → 9.6236·√3, sin(π/3) →
// √3/2, the azimuths' 0.866025403784439 and 0.866025403784438 both √3/2), each within 1e-15
// relative, the tolerance of ShortDecimal. Other floats, and exact rationals, are left alone.
std::optional<ExactForm> ShortExactForm(const GiNaC::numeric& n) {
  if (!n.is_real() || (n.is_rational() && (n.is_integer() || AsFraction(n) ||
                                           FiniteDecimalDigits(n) <= 15))) {
    return std::nullopt;
  }
  const double v = n.to_double();
  if (!std::isfinite(v) || v == 0.0) return std::nullopt;
  const double whole = std::round(v);
  if (std::abs(whole) < 1e15 && std::abs(whole - v) <= 1e-15 * std::abs(v)) {
    return ExactForm{GiNaC::numeric(static_cast<long>(whole)), 1};
  }
  for (const int k : {2, 3, 5, 6, 7}) {
    const std::string text = ShortDecimal(v / std::sqrt(static_cast<double>(k)));
    if (SignificantDigits(text) > 6 || text.find('e') != std::string::npos) continue;
    const GiNaC::numeric r = multibody::ExactDecimal(std::strtod(text.c_str(), nullptr));
    if (std::abs(r.to_double() * std::sqrt(static_cast<double>(k)) - v) > 1e-15 * std::abs(v)) {
      continue;
    }
    return ExactForm{r, k};
  }
  return std::nullopt;
}

// Whether the rational n prints as a fraction: a dyadic one with a denominator up to 1024
// (1/2, 3/4) or one that is no finite decimal with a denominator up to 1000 (2/3); others print
// as decimals (9.81, not 981/100).
bool AsFraction(const GiNaC::numeric& n) {
  if (!n.is_rational() || n.is_integer() || abs(n.numer()) > 1000000) return false;
  GiNaC::numeric d = n.denom();
  if (d <= 1024 && (GiNaC::numeric(1024) / d).is_integer()) return true;
  GiNaC::numeric rest = d;
  while ((rest / 2).is_integer()) rest = rest / 2;
  while ((rest / 5).is_integer()) rest = rest / 5;
  return rest != 1 && d <= 1000;
}

// A rational as a decimal: exactly if it is a finite decimal of at most 15 significant digits
// (the model file's 9.81, and sums and products of such numbers), else rounded to 15.
std::string Decimal(const GiNaC::numeric& n) {
  GiNaC::numeric scaled = n;
  int k = 0;
  while (!scaled.is_integer() && k < 40) {
    scaled *= 10;
    ++k;
  }
  std::ostringstream os;
  os << abs(scaled);
  std::string digits = os.str();
  const std::size_t first = digits.find_first_not_of('0');
  const std::size_t significant = first == std::string::npos ? 0 : digits.size() - first;
  if (!scaled.is_integer() || significant > 15) return ShortDecimal(n.to_double());
  if (k > 0) {
    if (digits.size() <= static_cast<std::size_t>(k)) {
      digits.insert(0, static_cast<std::size_t>(k) + 1 - digits.size(), '0');
    }
    digits.insert(digits.size() - static_cast<std::size_t>(k), ".");
  }
  return (n.is_negative() ? "-" : "") + digits;
}

}  // namespace hybridtest::symbolic::number_text
