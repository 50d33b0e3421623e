// See setup.h.
#include "hybridtest/transfer/openfresco/setup.h"

#include <fmt/core.h>

#include <cmath>
#include <limits>

#include "hybridtest/common/error.h"

namespace hybridtest::transfer::openfresco {
namespace {

double Dot(std::span<const double> a, std::span<const double> b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) s += a[i] * b[i];
  return s;
}

}  // namespace

void ValidateSetup(const ExpSetup& s) {
  if (s.transform.empty()) {
    throw ConfigError("openfresco.transform: empty; expected one row [[t1, ..., tn]]");
  }
  bool any = false;
  for (std::size_t i = 0; i < s.transform.size(); ++i) {
    if (!std::isfinite(s.transform[i])) {
      throw ConfigError(fmt::format("openfresco.transform[0][{}] = {}: expected a finite number",
                                    i, s.transform[i]));
    }
    any = any || s.transform[i] != 0.0;
  }
  if (!any) throw ConfigError("openfresco.transform: all zero; the actuator would never move");
  // The element forces, stiffness and displacements divide by |t|²: a row of 1e-200 would
  // underflow to 0 and send inf/NaN on the wire. A transform row is a set of direction
  // cosines and scales of order 1.
  const double norm = std::sqrt(Dot(s.transform, s.transform));
  if (!(norm >= 1e-6 && norm <= 1e6)) {
    throw ConfigError(fmt::format("openfresco.transform: |t| = {}: expected a row of direction "
                                  "cosines and scales with a length from 1e-6 to 1e6 (e.g. "
                                  "[[1.0]] or [[0.0, 1.0]])", norm));
  }
  if (!std::isfinite(s.initial_stiffness) || s.initial_stiffness < 0.0) {
    throw ConfigError(fmt::format("openfresco.initial_stiffness = {} N/m: expected a finite "
                                  "value >= 0", s.initial_stiffness));
  }
  if (!std::isfinite(s.p0)) throw ConfigError("openfresco: p0 is not finite");
}

double ActuatorCommand(const ExpSetup& s, std::span<const double> d) {
  for (const double v : d) {
    if (!std::isfinite(v)) return std::numeric_limits<double>::quiet_NaN();
  }
  return s.p0 + Dot(s.transform, d) * s.wire_units.metres_per_length_unit;
}

std::vector<double> ElementForces(const ExpSetup& s, double force) {
  const double f = force / s.wire_units.newtons_per_force_unit;
  std::vector<double> q(s.transform.size());
  for (std::size_t i = 0; i < q.size(); ++i) q[i] = s.transform[i] * f;
  return q;
}

std::vector<double> ElementStiffness(const ExpSetup& s, double stiffness) {
  const double k =
      stiffness * s.wire_units.metres_per_length_unit / s.wire_units.newtons_per_force_unit;
  const std::size_t n = s.transform.size();
  std::vector<double> K(n * n);
  for (std::size_t col = 0; col < n; ++col) {
    for (std::size_t row = 0; row < n; ++row) {
      K[col * n + row] = s.transform[row] * k * s.transform[col];
    }
  }
  return K;
}

std::vector<double> ElementDisplacement(const ExpSetup& s, double offset) {
  const double x = offset / s.wire_units.metres_per_length_unit;
  const double tt = Dot(s.transform, s.transform);
  std::vector<double> d(s.transform.size());
  for (std::size_t i = 0; i < d.size(); ++i) d[i] = s.transform[i] * x / tt;
  return d;
}

std::vector<double> ProjectOnActuator(const ExpSetup& s, std::span<const double> v) {
  const double scale = Dot(s.transform, v) / Dot(s.transform, s.transform);
  std::vector<double> out(s.transform.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = s.transform[i] * scale;
  return out;
}

}  // namespace hybridtest::transfer::openfresco
