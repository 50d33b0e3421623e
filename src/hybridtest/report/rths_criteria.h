#pragma once
// RthsCriteria: the evaluation criteria of the vRTHS benchmark (Silva et al. 2020) of a
// real-time run against its reference structure, i.e. the same run all-numerical (a perfect
// actuator: e.g. examples/real-time/storey-reference.yaml, the specimen on the `ideal` plant in
// virtual time). With NRMS(x, y) = σ(x − y)/σ(y)·100 and PEAK(x, y) = max|x − y|/max|y|·100
// (common/tracking.h), all in [%] except J1:
//
//   J1  tracking delay of the first physical slot's actuator: the cross-correlation peak of
//       its measured position against its command [ms]               (the run alone)
//   J2  NRMS(x_m, x_c)      J3  PEAK(x_m, x_c)                        (the run alone)
//   J4  NRMS(d_m, y1_ref)   J5  PEAK(d_m, y1_ref)  — floor 1: the slot's measured
//       displacement d_m = (position − p0)/(sign·scale) (the run config's setup) against the
//       reference's coordinate that the slot's displacement is (the model's slot coordinate),
//       or, for a slot whose displacement is not one coordinate (a damper's stroke q2 − q1),
//       the reference's own measured displacement of the slot (<slot>_position, its setup)
//   J6  NRMS(y2, y2_ref)    J7  NRMS(y3, y3_ref)   — floors 2 and 3: the first two coordinates
//   J8  PEAK(y2, y2_ref)    J9  PEAK(y3, y3_ref)     other than the slot's, in the model's order
//
// The benchmark's floors are the model's coordinates here. The run's committed rows (finite
// values) are compared at their times inside the reference's span, the reference interpolated
// linearly between its samples (its own sample where the times agree within 1e-12 s). A
// criterion that the models cannot give (no slot coordinate, fewer coordinates) is NaN.
#include <array>
#include <string>

#include <nlohmann/json.hpp>

#include "hybridtest/io/run_reader.h"

namespace hybridtest::report {

struct RthsCriteria {
  std::string slot;                  // the first physical slot of the run, e.g. "r1"
  std::array<std::string, 3> floor;  // the reference's channels of floors 1–3 ("" where none)
  std::array<double, 10> J{};        // J[1] … J[9] (J[0] unused); NaN where undefined
  long points = 0;                   // the run's rows compared with the reference
};

// True for a paced run: its sidecar holds statistics.real_time, or its config a real_time
// block.
bool IsRealTimeRun(const io::RunData& run);

// The criteria of `run` against `reference`. Throws IoError naming the file when the run has
// no physical slot, the reference lacks a floor's coordinate, or the runs do not overlap.
RthsCriteria ComputeRthsCriteria(const io::RunData& run, const io::RunData& reference);

// "J1 … J9" with their meaning, one per line, for a terminal.
std::string FormatRthsCriteria(const RthsCriteria& criteria);
// {"slot", "floors", "points", "J1_ms", "J2", … "J9"} (null where undefined).
nlohmann::json ToJson(const RthsCriteria& criteria);

}  // namespace hybridtest::report
