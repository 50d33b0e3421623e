#pragma once
// The site protocol (docs/multi-site.md): how a coordinator (the Session, through SiteClient)
// drives one physical site (SiteServer) in two phases. It uses the bench protocol's framing
// (frame.h: magic, version, type, sequence, length, CRC-32) and its HELLO, WELCOME, HOLD,
// HOLD_ACK, HEARTBEAT, ERROR and BYE messages; the transaction messages are:
//
//   PROPOSE   id, u16 n, n × f64 target [bench length unit]    → ACCEPT id | REFUSE
//   ACCEPT    id
//   REFUSE    id, str limit, f64 value [SI], f64 limit_value [SI], str reason
//   EXECUTE   id                                              → RESULT | ERROR
//   RESULT    id, u16 replayed (1: answered from the record), u16 n,
//             n × (f64 position [bench length unit], f64 force [bench force unit],
//                  f64 lab_time [s], f64 force_reversals)
//   QUERY     id                                              → RESULT | ERROR
//             (seq = 0, kQueryNow: every actuator's measurement now, read by the site's bench
//             WITHOUT moving — the coordinator's start check; ERROR BENCH if it cannot read so)
//
// A transaction id is (run, seq, step, stage, attempt): `run` names the coordinator's run
// (chosen once per process of the coordinator), `seq` counts its transactions at this site
// (1, 2, ...); (run, seq) is the key a site applies at most once. step (the Session's step,
// −1 before the test), stage (Runge–Kutta stage) and attempt (0, 1, ... for the same step
// and stage) say where it belongs, for the journal and messages.
//   id = str run, u32 seq, u32 step_hi, u32 step_lo (two's complement i64), u32 stage
//        (two's complement i32), u32 attempt
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "hybridtest/transfer/frame.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer::site {

inline constexpr std::size_t kMaxRunTagBytes = 64;  // a run tag's length. Unit: [bytes].
// The seq of a QUERY that asks for the measurement now (no transaction has seq 0).
inline constexpr std::uint32_t kQueryNow = 0;

struct TransactionId {
  std::string run;        // the coordinator's run tag (≤ kMaxRunTagBytes)
  std::uint32_t seq = 0;  // 1, 2, ... per site and run
  long step = 0;
  int stage = 0;
  int attempt = 0;
  bool SameKey(const TransactionId& o) const { return seq == o.seq && run == o.run; }
  std::string Text() const;  // "run/seq (step 12, stage 1, attempt 0)"
};

// Throws TransferError unless `run` is a run tag (1 to kMaxRunTagBytes of [A-Za-z0-9._-]).
void CheckRunTag(const std::string& run);

struct Proposal {
  TransactionId id;
  std::vector<double> targets;  // (n) [bench length unit]
};

struct Refusal {
  TransactionId id;
  std::string limit;          // the SafetyStop limit name ("stroke", "increment", ...)
  double value = 0.0;         // the offending value (SI)
  double limit_value = 0.0;   // the limit (SI)
  std::string reason;         // the site's words
};

struct Result {
  TransactionId id;
  bool replayed = false;                  // answered from the site's record, nothing moved
  std::vector<Measurement> measurements;  // (n) bench units
};

Frame EncodePropose(std::uint32_t sequence, const Proposal& p);
Frame EncodeAccept(std::uint32_t sequence, const TransactionId& id);
Frame EncodeRefuse(std::uint32_t sequence, const Refusal& r);
// EXECUTE or QUERY.
Frame EncodeIdOnly(MessageType type, std::uint32_t sequence, const TransactionId& id);
Frame EncodeResult(std::uint32_t sequence, const Result& r);

// Decoders check the type and the exact payload; they throw TransferError naming the field.
Proposal DecodePropose(const Frame& frame);
TransactionId DecodeAccept(const Frame& frame);
Refusal DecodeRefuse(const Frame& frame);
TransactionId DecodeIdOnly(const Frame& frame, MessageType expected);
Result DecodeResult(const Frame& frame);

}  // namespace hybridtest::transfer::site
