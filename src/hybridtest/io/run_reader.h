#pragma once
// RunData and LoadRun: read back a run written by Journal (see docs/results-format.md).
//
// Parsing is strict: the first line must hold the channel names, every later line exactly one
// number per channel. A malformed line throws IoError naming file:line. The one exception is
// the LAST line when it lacks its terminating newline: that is what a crash in the middle of
// a write leaves behind, so it is dropped and a note is added to RunData::warnings.
//
// Metadata come from the JSON sidecar (SidecarPath(csv_path)) when it exists. Without one,
// units and descriptions are inferred from the channel names (InferChannelUnit below).
#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <string>
#include <string_view>
#include <vector>

#include "hybridtest/io/journal.h"

namespace hybridtest::io {

struct RunData {
  std::string csv_path;
  std::vector<Channel> channels;      // one per column, in CSV order
  Eigen::MatrixXd values;             // (rows × channels), SI units
  nlohmann::json metadata;            // the sidecar, or null if there is none
  std::vector<std::string> warnings;  // e.g. "dropped a truncated last line (line 1234)"

  long num_rows() const { return static_cast<long>(values.rows()); }
  int num_channels() const { return static_cast<int>(channels.size()); }

  // Column index of a channel, or -1 if the run has no such channel.
  int Column(std::string_view name) const;
  bool Has(std::string_view name) const { return Column(name) >= 0; }

  // The values of one channel, (rows × 1). Throws IoError naming the channel, the file and
  // the channels that do exist.
  Eigen::VectorXd Get(std::string_view name) const;

  // Unit of a channel ("m", "N", ...): from the sidecar if present, else inferred from the
  // name. Throws IoError like Get() for an unknown channel.
  std::string Unit(std::string_view name) const;

  // Description of a channel (from the sidecar, else inferred). Throws like Get().
  std::string Description(std::string_view name) const;
};

// Reads a run. Throws IoError if the file cannot be opened, is empty, has a malformed line
// (file:line), or has a sidecar that is not valid JSON.
RunData LoadRun(const std::string& csv_path);

// What a channel is, by the naming convention of docs/results-format.md.
enum class ChannelKind {
  kTime,            // "t"                                   [s]
  kCoordinate,      // "q<n>"                                [m] (or [rad]: see below)
  kSpeed,           // "u<n>"                                [m/s] (or [rad/s])
  kRestoringForce,  // "r<n>"                                [N]
  kPhysical,        // "<slot>_command|_position|_force|_lab_time"
  kOther,           // anything else
};

struct ChannelClass {
  ChannelKind kind = ChannelKind::kOther;
  int index = 0;        // n for q<n>, u<n>, r<n>; 0 otherwise
  std::string slot;     // for kPhysical: the slot name, e.g. "r1"
  std::string field;    // for kPhysical: "command", "position", "force" or "lab_time"
};

// Classifies a channel name by the convention above.
ChannelClass ClassifyChannel(std::string_view name);

// Unit inferred from a channel name alone, used when a run has no sidecar:
//   t → s, q<n> → m, u<n> → m/s, r<n> → N, <slot>_command → m, <slot>_position → m,
//   <slot>_force → N, <slot>_lab_time → s, anything else → "" (unknown).
// The name cannot tell a rotation from a translation: q<n> is assumed to be a length. Runs
// written by hybridtest always carry a sidecar with the true units.
std::string InferChannelUnit(std::string_view name);

// A short description inferred from a channel name ("generalized coordinate 2", ...).
std::string InferChannelDescription(std::string_view name);

}  // namespace hybridtest::io
