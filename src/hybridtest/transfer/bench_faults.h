#pragma once
// TEST FACILITY: the one fault injector of hybridtest's benches. Never enable it on a real test
// rig: every fault breaks the protocol or the measurement on purpose, so that tests can check
// that the client, the runner and their safety monitors detect it.
//
// One convention for both places a fault can be injected:
//  - `hybridtest bench --inject KIND@N` (BenchServer, every kind), and
//  - an emulated bench's `faults: [{at: N, kind: KIND, force_N: F}]` (EmulatedBench, the
//    measurement kinds nan, inf, spike and silence; the wire kinds need the server).
// A fault fires once, at the N-th command the bench receives: N is 1-based and counts every
// command over the bench's (or the server's) whole lifetime, refused ones included.
//
//   nan        the measured force is NaN
//   inf        the measured force is +Inf
//   spike      the measured force is increased by `spike_force` [N] (default 1e5 N, ten times
//              the default actuator capacity), converted to the bench's force unit
//   silence    command N is not answered (the bench holds; the caller's timeout fires)
//   corrupt    wire only: one payload byte of the MEASUREMENT frame is flipped after its CRC
//   stale_seq  wire only: the MEASUREMENT echoes sequence number N_seq − 1 instead of N_seq
//   duplicate  wire only: the previous MEASUREMENT frame is sent again (byte for byte) before
//              the answer; at the first command, the answer itself is sent twice
//   close      wire only: the connection is closed on receipt of command N (the bench holds)
//
// The measurement kinds corrupt what the bench reports AFTER the bench's own checks, as a
// broken wire or sensor would.
#include <string>
#include <vector>

#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer {

enum class FaultKind { kNan, kInf, kSpike, kSilence, kCorrupt, kStaleSeq, kDuplicate, kClose };

inline constexpr double kDefaultSpikeForce = 1e5;  // Unit: [N].

struct Fault {
  FaultKind kind = FaultKind::kNan;
  long command = 1;                        // 1-based index of the command at which it fires
  double spike_force = kDefaultSpikeForce;  // added force for kSpike. Unit: [N].
};

// The largest command index a fault may name (a sanity bound on user input).
inline constexpr long kMaxFaultCommand = 1'000'000'000'000L;

// "nan", "spike", ...
std::string FaultKindName(FaultKind kind);
// The kind named `name`; throws ConfigError naming `where` and the accepted names.
FaultKind ParseFaultKind(const std::string& name, const std::string& where);

// Parses "KIND@N" (e.g. "spike@3"). Throws ConfigError naming `where`, the text given and the
// accepted kinds.
Fault ParseFault(const std::string& text, const std::string& where);

// The fault of `kind` that fires at `command`, if any (nullptr otherwise).
const Fault* FindFault(const std::vector<Fault>& faults, FaultKind kind, long command);
bool HasFault(const std::vector<Fault>& faults, FaultKind kind, long command);

// Applies every measurement fault (nan, inf, spike) that fires at `command` to `measurement`
// (in bench units, converted with `units`).
void ApplyMeasurementFaults(const std::vector<Fault>& faults, long command,
                            const BenchUnits& units, Measurement& measurement);

}  // namespace hybridtest::transfer
