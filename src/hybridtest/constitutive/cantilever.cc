#include "hybridtest/constitutive/cantilever.h"

#include <cmath>

#include <fmt/format.h>

#include "hybridtest/common/error.h"

namespace hybridtest::constitutive {
namespace {

void RequirePositive(const char* name, double value) {
  if (!(std::isfinite(value) && value > 0.0)) {
    throw ConfigError(fmt::format("cantilever: {} = {}: expected a finite positive value in SI "
                                  "units (metres for lengths, pascals for the modulus)",
                                  name, value));
  }
}

}  // namespace

double CantileverTipStiffness(double length, double width, double thickness,
                              double youngs_modulus) {
  RequirePositive("length", length);
  RequirePositive("width", width);
  RequirePositive("thickness", thickness);
  RequirePositive("youngs_modulus", youngs_modulus);
  const double second_moment = width * thickness * thickness * thickness / 12.0;  // [m^4]
  return 3.0 * youngs_modulus * second_moment / (length * length * length);
}

std::unique_ptr<LinearSpring> MakeCantileverSpring(double length, double width, double thickness,
                                                   double youngs_modulus) {
  const double k = CantileverTipStiffness(length, width, thickness, youngs_modulus);
  return std::make_unique<LinearSpring>(
      k, fmt::format("cantilever {:g}x{:g}x{:g} mm, E={:g} GPa (k={:.6g} N/m)", length * 1e3,
                     width * 1e3, thickness * 1e3, youngs_modulus * 1e-9, k));
}

}  // namespace hybridtest::constitutive
