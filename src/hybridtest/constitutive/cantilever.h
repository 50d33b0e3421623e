#pragma once
// Tip stiffness of an elastic, prismatic, rectangular cantilever loaded at its free end about
// its weak axis (Euler–Bernoulli):
//
//   k = 3 E I / L³,   I = b t³ / 12
//
// The seed paper's specimen, a 500 × 100 × 5 mm steel beam with E = 210 GPa, gives
// k = 5250 N/m.
#include <memory>

#include "hybridtest/constitutive/linear_spring.h"

namespace hybridtest::constitutive {

// length L, width b, thickness t [m]; youngs_modulus E [Pa]. Returns k [N/m].
// Throws ConfigError unless every argument is finite and positive.
double CantileverTipStiffness(double length, double width, double thickness,
                              double youngs_modulus);

// A LinearSpring with the cantilever's tip stiffness, described as
// "cantilever 500x100x5 mm, E=210 GPa (k=5250 N/m)".
std::unique_ptr<LinearSpring> MakeCantileverSpring(double length, double width, double thickness,
                                                   double youngs_modulus);

}  // namespace hybridtest::constitutive
