#pragma once
// Display units for figures and reports: the run is SI inside (lengths in m, forces in N); a
// lab reads its rig in mm and kN. PlotUnits converts a channel's recorded unit for drawing only:
//   m → <length>, m/s → <length>/s, m/s^2 → <length>/s^2, N → <force>,
//   N·m (or N*m, N.m) → <force>·m, N/m → <force>/<length>.
// Any other unit (rad, rad/s, s, ...) is drawn as recorded.
//
// Spec strings (`hybridtest plot --units`, `hybridtest report --units`): comma-separated
// tokens, each a unit ("mm", "kN") whose quantity is recognised, or quantity=unit
// ("length=mm", "force=kN"). Lengths: m, cm, mm, um (µm); forces: N, kN, MN.
#include <string>

namespace hybridtest::report {

struct PlotUnits {
  std::string length = "m";  // one of m, cm, mm, um
  std::string force = "N";   // one of N, kN, MN

  // True when nothing is converted.
  bool IsSi() const { return length == "m" && force == "N"; }
  // Factor from the recorded unit to the displayed one (1 for units it does not convert).
  double Factor(const std::string& recorded_unit) const;
  // The displayed unit for a recorded unit ("" stays "").
  std::string Label(const std::string& recorded_unit) const;
};

// Parses a spec as above. Throws ConfigError naming the token and the accepted units.
PlotUnits ParsePlotUnits(const std::string& spec);

}  // namespace hybridtest::report
