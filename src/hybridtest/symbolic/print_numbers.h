#pragma once
// Numbers as the printers write them (print_expression.h; not C, whose literals are exact
// round trips, print_c.h): a number as the model file wrote it, not the last bits of the
// floating-point arithmetic that computed it (issue 47: "no printed number has more digits
// than the model file gave").
#include <ginac/ginac.h>

#include <optional>
#include <string>

namespace hybridtest::symbolic::number_text {

// The shortest decimal within 1e-15 relative of v (1.57, not 1.5699999999999998); at most
// 15 significant digits.
std::string ShortDecimal(double v);

// Whether the rational n prints as a fraction (1/2, 3/4, 2/3) rather than a decimal (9.81).
bool AsFraction(const GiNaC::numeric& n);

// A rational as a decimal: exact if it has at most 15 significant digits, else rounded.
std::string Decimal(const GiNaC::numeric& n);

// factor · √root (root 1: the factor alone), factor an exact rational.
struct ExactForm {
  GiNaC::numeric factor;
  int root = 1;
};

// The exact number n stands for if it came from floating-point arithmetic (a float, or a
// rational with no decimal of ≤ 15 digits that is no small fraction: the exact value of a
// double such as sin(2π/3)) and is a short one: a
// whole number (−1.0000000000000002 → −1), or a decimal of at most 6 significant digits times
// √k, k ∈ {2, 3, 5, 6, 7} (sin(2π/3) → √3/2, g m_b sin(2π/3) → 9.6236·√3), within 1e-15
// relative. Nothing otherwise (the number prints as it is).
std::optional<ExactForm> ShortExactForm(const GiNaC::numeric& n);

}  // namespace hybridtest::symbolic::number_text
