#pragma once
// What a run writes about itself: the journal's channels and the sidecar's metadata, derived
// from the config, the model and the substructures. Pure functions, so the channel layout is
// defined once and tested on its own.
//
// Channels (SI): t [s]; q1..qn; u1..un (units from the model); r1..rm [N] (the static
// restoring forces at the committed state); then for each physical substructure of slot S:
// S_command [m], S_position [m], S_force [N], S_lab_time [s] (its exchange at the committed
// state, i.e. stage 0 of the step); last, the forces of the model's constraints that record
// them (ConstraintSpec::record_force), one channel per constraint row:
// <constraint>_reaction, or <constraint>_reaction_<x|y|z> for a component (the name with every
// character other than a letter, digit or _ made _), in ConstraintSpec::force_unit.
#include <memory>
#include <vector>

#include "hybridtest/io/run_spec.h"
#include "hybridtest/io/journal.h"
#include "hybridtest/substructures/substructure.h"

namespace hybridtest::runner {

using SubstructureList = std::vector<std::unique_ptr<substructures::Substructure>>;

std::vector<io::Channel> JournalChannels(const io::RunSpec& spec);

// The constraint rows (indices of B u + c = 0) whose forces the journal records, in the order
// of their channels (the last ones of a row).
std::vector<int> RecordedConstraintRows(const multibody::Model& model);

// Channels of the per-stage record of physical exchanges: step, stage, t, and for each
// physical substructure its command, position, force, lab time and the reversals of the
// specimen force within the move (S_force_reversals; 0 where the bench cannot see them).
std::vector<io::Channel> StageChannels(const io::RunSpec& spec);

// An upper bound of the journal rows a run writes (adaptive schemes: at their smallest step;
// MR-OS: a row per substep). Used to check that the output fits on the disk.
long MaxJournalRows(const io::RunSpec& spec);

io::JournalMetadata JournalMetadataFor(const io::RunSpec& spec,
                                       const SubstructureList& subs, const std::string& command);

}  // namespace hybridtest::runner
