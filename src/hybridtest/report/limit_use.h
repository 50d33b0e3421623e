#pragma once
// How much of each safety limit a physical substructure used during a run, as a fraction of
// the limit (1 = at the limit), for figures and the report's summary.
//
// The limits are the runner's own (SI, the `safety:` block of the slot; docs/safety.md):
// from the sidecar's substructures[].safety object when the sidecar has one, else from the
// `substructures.<slot>.safety` block of the config text recorded in the sidecar (`safety:
// defaults` gives transfer::SafetyLimits' defaults). Use, per recorded sample:
//   stroke         command / stroke_max where the command is ≥ 0, command / stroke_min below
//   max_increment  |command − previous command| / max_increment, between consecutive
//                  exchanges: every stage's from <run>.stages.csv when it exists, else between
//                  the journal's rows (which then only bounds the per-stage increments below)
//   force_soft     |measured force| / force_soft (the check itself uses the predicted force)
//   force_hard     |measured force| / force_hard
// Samples without a value (NaN: a substep row without a specimen sample) are skipped.
#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

#include "hybridtest/io/run_reader.h"
#include "hybridtest/report/plot_layout.h"
#include "hybridtest/transfer/safety.h"

namespace hybridtest::report {

// The limits of `slot`, or nothing when the sidecar records none (no config, not physical).
std::optional<transfer::SafetyLimits> FindSlotLimits(const io::RunData& run,
                                                     const std::string& slot);
// The limits of actuator `actuator` (0-based) of the physical substructure `substructure` (its
// key in the config); −1: a substructure of one actuator (FindSlotLimits). A limit given as a
// list holds one value per actuator; a scalar applies to every actuator (docs/safety.md).
std::optional<transfer::SafetyLimits> FindActuatorLimits(const io::RunData& run,
                                                         const std::string& substructure,
                                                         int actuator);

struct LimitUse {
  std::string limit;        // "stroke", "max_increment", "force_soft", "force_hard"
  std::string measure;      // what is divided by the limit, e.g. "|measured force|"
  double limit_value = 0;   // the limit. Unit: [m] or [N]
  Eigen::VectorXd t;        // (n × 1) time of each sample. Unit: [s]
  Eigen::VectorXd use;      // (n × 1) fraction of the limit, ≥ 0
  double peak = 0;          // largest use; 0 without samples
  double peak_t = 0;        // when. Unit: [s]
};

// The limits of one actuator's channels: FindActuatorLimits for an actuator of several,
// FindSlotLimits for a substructure of one actuator.
std::optional<transfer::SafetyLimits> FindLimitsOf(const io::RunData& run,
                                                   const PhysicalChannels& channels);

// The four uses above for one actuator (PhysicalChannels: one actuator's channels, of a
// substructure of one actuator or one of several); empty when its limits are unknown or it has
// no recorded command or force.
std::vector<LimitUse> CalcLimitUse(const io::RunData& run, const PhysicalChannels& slot);

// The per-slot limits of a physical substructure that serves several slots (`safety.slots`:
// max_displacement [m] and max_force [N], one value per slot in the order of `slots:`), and
// their use over the journal's rows:
//   max_displacement  |slot coordinate| / max_displacement (the slot's coordinate channel, when
//                     the model names one for the slot; the slot's displacement is then that
//                     coordinate)
//   max_force         |r of the slot| / max_force (the slot's restoring-force channel)
struct SlotLimitUse {
  std::string slot;  // the model's slot, e.g. "r_flap"
  LimitUse use;      // `limit` is "max_displacement" or "max_force"
};
std::vector<SlotLimitUse> CalcSlotLimitUse(const io::RunData& run, const RunLayout& layout,
                                           const std::string& substructure);

}  // namespace hybridtest::report
