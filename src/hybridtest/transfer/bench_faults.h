#pragma once
// TEST FACILITY: fault injection for BenchServer. Never enable it on a real test rig: every
// fault breaks the protocol or the measurement on purpose, so that tests can check that the
// client and the runner detect it.
//
// A fault is written KIND@N and fires once, at the N-th COMMAND the server receives (1-based,
// counted over the server's whole lifetime, across client sessions):
//
//   nan        the MEASUREMENT's force is NaN
//   spike      the MEASUREMENT's force is multiplied by 100
//   corrupt    one payload byte of the MEASUREMENT frame is flipped after its CRC was computed
//   stale_seq  the MEASUREMENT echoes sequence number N_seq − 1 instead of N_seq
//   duplicate  the previous MEASUREMENT frame is sent again (byte for byte) before the answer;
//              at the first command, the answer itself is sent twice
//   silence    command N is neither executed nor answered (the bench holds; the session stays)
//   close      the connection is closed on receipt of command N (the bench holds)
#include <string>
#include <vector>

namespace hybridtest::transfer {

enum class FaultKind { kNan, kSpike, kCorrupt, kStaleSeq, kDuplicate, kSilence, kClose };

struct Fault {
  FaultKind kind = FaultKind::kNan;
  long command = 1;  // 1-based index of the COMMAND at which the fault fires
};

// "nan", "spike", ...
std::string FaultKindName(FaultKind kind);

// Parses "KIND@N" (e.g. "spike@3"). Throws ConfigError naming `where`, the text given and the
// accepted kinds.
Fault ParseFault(const std::string& text, const std::string& where);

// The fault of `kind` that fires at `command`, if any.
bool HasFault(const std::vector<Fault>& faults, FaultKind kind, long command);

}  // namespace hybridtest::transfer
