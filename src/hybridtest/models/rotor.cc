// The paper's rotor, written with the public multibody API. See rotor.h.
#include "hybridtest/models/rotor.h"

#include <fmt/core.h>

#include <cmath>
#include <numbers>

#include "hybridtest/common/error.h"
#include "hybridtest/models/model_checks.h"
#include "hybridtest/multibody/jet.h"

namespace hybridtest::models {

using multibody::FrameId;
using multibody::PointId;
using multibody::ScalarField;
using multibody::Vector3;

namespace {
// Blade-specific parameter names and what they mean.
struct BladeParameter {
  const char* name;
  const char* unit;
  const char* description;
};
constexpr BladeParameter kBladeParameters[] = {
    {"l_b", "m", "blade length"},
    {"m_b", "kg", "blade tip mass"},
    {"zeta_b", "1/s", "blade mass-proportional damping"},
    {"k_b", "N/m", "blade stiffness (default numerical substructure)"},
    {"f_w", "N", "wind load"},
};
}  // namespace

static_assert(kMaxRotorBlades == multibody::kMaxJetCoordinates - 1,
              "the hub's coordinate and one per blade");

int CheckRotorBlades(double blades, std::string_view where) {
  if (!(blades >= 1 && blades <= kMaxRotorBlades && blades == std::floor(blades))) {
    throw ConfigError(fmt::format(
        "{} = {:.15g}: expected a whole number of blades from 1 to {} (the Kane engine takes at "
        "most {} coordinates, the hub's and one per blade)", where, blades, kMaxRotorBlades,
        multibody::kMaxJetCoordinates));
  }
  return static_cast<int>(blades);
}

ParameterSet RotorDefaultParameters(int blades) {
  CheckRotorBlades(blades, "model.blades");
  ParameterSet p;
  p.Add("l_b", 0.5, "m", "blade length (all blades)");
  p.Add("m_b", 1.96, "kg", "blade tip mass (all blades)");
  p.Add("zeta_b", 1.0, "1/s", "blade mass-proportional damping (all blades)");
  p.Add("k_b", 7.2e3, "N/m", "blade stiffness (all blades)");
  p.Add("f_w", 100.0, "N", "wind load (all blades)");
  p.Add("I_g", 0.1, "kg·m²", "geartrain moment of inertia");
  p.Add("d_g", 100.0, "N·m·s", "geartrain (generator) damping");
  p.Add("g", 9.82, "m/s²", "gravity");
  p.Add("t0", 0.5, "s", "ramping time constant of gravity and wind, Eq. (12)");
  for (int i = 1; i <= blades; ++i) {
    for (const BladeParameter& bp : kBladeParameters) {
      p.Add(fmt::format("blade{}.{}", i, bp.name), std::nan(""), bp.unit,
            fmt::format("{} of blade {} (default: the all-blades value)", bp.description, i));
    }
    p.Add(fmt::format("blade{}.psi", i), 2.0 * std::numbers::pi * (i - 1) / blades, "rad",
          fmt::format("initial azimuth of blade {}", i));
  }
  return p;
}

BuiltModel BuildRotor(int blades, const ParameterSet& in) {
  const int N = CheckRotorBlades(blades, "model.blades");
  // Resolve per-blade values: an unset (NaN) blade value inherits the all-blades value.
  ParameterSet p;
  for (const auto& param : in.all()) {
    double value = param.value;
    std::string description = param.description;
    const auto dot = param.name.find('.');
    if (std::isnan(value) && dot != std::string::npos) {
      value = in.Get(param.name.substr(dot + 1));
      description += fmt::format("; inherited from {}", param.name.substr(dot + 1));
    }
    p.Add(param.name, value, param.unit, description);
  }
  for (const char* name : {"I_g", "t0"}) RequirePositive(p, name);
  for (const char* name : {"d_g", "g"}) RequireNonNegative(p, name);
  const double I_g = p.Get("I_g"), d_g = p.Get("d_g"), g = p.Get("g"), t0 = p.Get("t0");

  std::vector<multibody::QuantityInfo> coordinates;
  std::vector<multibody::QuantityInfo> speeds;
  for (int i = 1; i <= N; ++i) {
    coordinates.push_back({fmt::format("q{}", i), "m", fmt::format("tip deflection of blade {}", i)});
    speeds.push_back({fmt::format("u{}", i), "m/s", fmt::format("tip deflection rate of blade {}", i)});
  }
  coordinates.push_back({fmt::format("q{}", N + 1), "rad", "hub angle"});
  speeds.push_back({fmt::format("u{}", N + 1), "rad/s", "hub angular speed"});
  multibody::ModelBuilder b(coordinates, speeds);

  const int hub = N;  // index of the hub coordinate
  // The ramp of Eq. (12), ρ(t) = 1 − e^{−t/t0}: evaluated once per right-hand side.
  const int ramp = b.AddTimeFunction("ramp", [t0](const auto& t) {
    using T = std::decay_t<decltype(t)>;
    using std::exp;
    return T(1.0 - exp(-t / t0));
  });
  const FrameId H = b.AddFrameAboutAxis("H", b.newtonian(), Eigen::Vector3d::UnitZ(),
                                        ScalarField::Coordinate(hub));
  b.AddRigidBody("hub", H, b.origin(), 0.0, Eigen::Vector3d(0.0, 0.0, I_g).asDiagonal());

  std::vector<double> lengths(N), dampings(N), stiffness(N);
  for (int i = 0; i < N; ++i) {
    const std::string prefix = fmt::format("blade{}.", i + 1);
    for (const char* name : {"l_b", "m_b", "k_b"}) RequirePositive(p, prefix + name);
    RequireNonNegative(p, prefix + "zeta_b");
    const double l_b = p.Get(prefix + "l_b"), m_b = p.Get(prefix + "m_b");
    const double zeta_b = p.Get(prefix + "zeta_b"), f_w = p.Get(prefix + "f_w");
    lengths[i] = l_b;
    dampings[i] = zeta_b * m_b;
    stiffness[i] = p.Get(prefix + "k_b");

    const FrameId B = b.AddFrameAboutAxis(fmt::format("B{}", i + 1), H, Eigen::Vector3d::UnitZ(),
                                          ScalarField::Constant(p.Get(prefix + "psi")));
    const PointId P = b.AddPoint(fmt::format("P{}", i + 1), b.origin(), B,
                                 {ScalarField::Constant(l_b), ScalarField::Coordinate(i), {}});
    b.AddParticle(fmt::format("tip{}", i + 1), P, m_b);
    b.AddRestoringForceSlot(fmt::format("r{}", i + 1),
                            fmt::format("static restoring force of blade {}", i + 1),
                            ScalarField::Coordinate(i));
    const double c = zeta_b * m_b;
    // Eq. (9) along b̂_iy: −(r_i^s + ζ_b m_b u_i) + ρ f_w.
    b.AddForce(fmt::format("blade{} restoring force and wind", i + 1), P, B,
               [=](const auto& a) {
                 using T = std::decay_t<decltype(a.t)>;
                 return Vector3<T>(T(0.0), -(a.r[i] + c * a.u[i]) + a.time_function(ramp) * f_w,
                                   T(0.0));
               });
    // Eq. (9): gravity m_b G(t) n̂_x.
    b.AddForce(fmt::format("blade{} gravity", i + 1), P, b.newtonian(), [=](const auto& a) {
      using T = std::decay_t<decltype(a.t)>;
      return Vector3<T>(m_b * g * a.time_function(ramp), T(0.0), T(0.0));
    });
  }
  // Eq. (10): generator damping and the blades' root reactions on the hub.
  b.AddTorque("hub", H, b.newtonian(), [=](const auto& a) {
    using T = std::decay_t<decltype(a.t)>;
    T tz = -d_g * a.u[hub];
    for (int i = 0; i < N; ++i) tz += (a.r[i] + dampings[i] * a.u[i]) * lengths[i];
    return Vector3<T>(T(0.0), T(0.0), tz);
  });

  BuiltModel built{"rotor",
                   fmt::format("wind-turbine rotor with {} blades (Nordtorp et al.)", N),
                   std::move(p), std::move(b).Build(), stiffness};
  return built;
}

}  // namespace hybridtest::models
