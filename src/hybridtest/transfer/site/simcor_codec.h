#pragma once
// UI-SimCor's ASCII protocol as a codec of the site (docs/multi-site.md "UI-SimCor modules"):
// pure functions, no socket. SiteServer uses it on a connection whose first byte is a
// lowercase letter (a bench-protocol frame begins with 'H'), when the site was started with
// --simcor; the transaction rules stay the site's own (site_server.h).
//
// One message per line: fields separated by TAB, the line ended by LF (a CR before it is
// dropped), printable ASCII only, at most kMaxLineBytes. Commands supported:
//
//   open-session      [ADDRESS [SYSTEM]]                        → OK
//   propose           ID  (ADDRESS (AXIS displacement VALUE)+)+ → OK | NOT OK (refused)
//   execute           ID  [ADDRESS]                             → OK | NOT OK
//   get-control-point ID|dummy  ADDRESS+                        → OK ADDRESS (AXIS q VALUE)+ ...
//   close-session     [...]                                     → OK, the connection ends
//
// ID is NAME or NAME[STEP SUBSTEP CORRECTION] (UI-SimCor: "trans" + a time stamp, steps from
// 1). An ADDRESS is a field containing "MDL" ("MDL-00-01:LBCB1"). AXIS is x, y or z; every
// displacement triple is one actuator target, in the order sent. VALUE [bench length unit].
//
// Answers: "OK\t0\tECHO\tTEXT" or "NOT OK\t0\tECHO\tREASON" (ECHO: the id field as sent, or
// the address); a get-control-point answer is "OK\t0\tECHO" then, per address, ADDRESS and
// (AXIS displacement P, AXIS force F) per actuator [bench length unit, bench force unit]. TEXT
// and REASON never hold a TAB or "MDL" (UI-SimCor's reader would take it for an address).
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "hybridtest/transfer/site/site_protocol.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer::site::simcor {

inline constexpr std::size_t kMaxLineBytes = 4096;  // one message with its LF. Unit: [bytes].
inline constexpr std::size_t kMaxValues = 64;       // displacement targets per propose
inline constexpr std::size_t kMaxAddresses = 64;    // addresses per get-control-point

enum class Command { kOpenSession, kCloseSession, kPropose, kExecute, kGetControlPoint };

struct ControlPoint {
  std::string address;  // "MDL-00-01:LBCB1"
  std::string axis;     // "x", "y" or "z"
};

struct Request {
  Command command = Command::kOpenSession;
  std::string echo;   // the id field as sent (or the address, or the command): answered back
  // The site's transaction id: run = NAME, or NAME-STEP-SUBSTEP-CORRECTION when the id has
  // steps (each distinct UI-SimCor id is its own key); seq = 1; step = STEP, stage = SUBSTEP,
  // attempt = CORRECTION (step −1 without them).
  TransactionId id;
  bool dummy = false;               // get-control-point without a transaction ("dummy")
  std::vector<ControlPoint> points; // propose: one per target; get-control-point: asked
  std::vector<double> targets;      // propose. Unit: bench length unit.
};

struct PointReading {
  ControlPoint point;
  Measurement measured;  // bench units
};

// True for a first byte that begins a UI-SimCor line (a lowercase ASCII letter).
bool BeginsLine(std::uint8_t first);

// The ServerLoop's Measure: the size of the line begun in `bytes` (through its LF), or
// bytes.size() + 1 while the LF is missing. Throws TransferError for a byte that is neither
// printable ASCII nor TAB, CR, LF, or for a line longer than kMaxLineBytes.
std::size_t MeasureLine(std::span<const std::uint8_t> bytes);

// Parses one line (with or without its LF). Throws TransferError naming the field (1-based),
// what was expected and what was sent.
Request ParseLine(std::span<const std::uint8_t> line);

// The field to echo in an answer to `line` that could not be parsed: its id field when it
// has one that is safe to send back, else "error".
std::string EchoOf(std::span<const std::uint8_t> line);

// Answers, each one line ending in LF.
std::string FormatOk(const std::string& echo, const std::string& text);
std::string FormatNotOk(const std::string& echo, const std::string& reason);
std::string FormatControlPoints(const std::string& echo, std::span<const PointReading> points);

}  // namespace hybridtest::transfer::site::simcor
