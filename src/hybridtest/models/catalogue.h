#pragma once
// The built-in models, by name. Each is written with the public multibody API, exactly as a
// user would write their own.
//
//   rotor            the paper's wind-turbine rotor: N blades (tip deflections q1..qN [m]) and
//                    the hub angle q(N+1) [rad]; one restoring-force slot per blade (rotor.h)
//   double_pendulum  planar double pendulum of two point masses (double_pendulum.h)
//   spinning_top     3D rigid body with a full inertia dyadic about a fixed pivot; speeds are
//                    body-frame angular velocity components (spinning_top.h)
#include <string>
#include <string_view>
#include <vector>

#include "hybridtest/models/parameters.h"
#include "hybridtest/multibody/model.h"

namespace hybridtest::models {

struct BuiltModel {
  std::string name;
  std::string description;
  ParameterSet parameters;      // resolved values
  multibody::Model model;
  // Stiffness of the default numerical substructure of each slot, r^s = k·d [N/m].
  std::vector<double> slot_stiffness;
};

std::vector<std::string> ModelNames();

// The rotor's blade count: a whole number from 1 to kMaxRotorBlades (the engine takes at most
// multibody::kMaxJetCoordinates coordinates: the hub's and one per blade). The one bound every
// front applies (a run config's model.blades, --blades, Python's Model.builtin) before anything
// is allocated. Returns `blades`; throws ConfigError "<where> = <blades>: expected a whole
// number of blades from 1 to 31 (...)" otherwise.
inline constexpr int kMaxRotorBlades = 31;
int CheckRotorBlades(double blades, std::string_view where);

// Default parameters of a model; `blades` is used by the rotor only. Throws ConfigError for an
// unknown name (listing the known ones) or a blade count outside CheckRotorBlades.
ParameterSet DefaultParameters(const std::string& name, int blades);

// Builds a model from (possibly overridden) parameters. Throws ConfigError for bad values
// (e.g. a non-positive mass), naming the parameter.
BuiltModel BuildModel(const std::string& name, int blades, const ParameterSet& parameters);

}  // namespace hybridtest::models
