#pragma once
// Messages of the hybridtest bench protocol, version 1: the payload of each frame type and
// its encoding (docs/protocol.md is the spec; frame.h the framing). Payload fields are
// little-endian; f64 is IEEE-754 binary64; str is a u16 byte count followed by UTF-8 bytes.
//
//   HELLO          u16 version, str token, str client_name
//   WELCOME        u16 version, str description, f64 metres_per_length_unit,
//                  f64 newtons_per_force_unit, str length_name, str force_name,
//                  f64 stroke_min [m], f64 stroke_max [m], f64 max_increment [m],
//                  f64 force_soft [N], f64 force_hard [N], f64 heartbeat_timeout [s]
//                  (u16 actuators, only for a bench of several actuators)
//   COMMAND        f64 position [bench length unit] (n of them for n actuators)
//   MEASUREMENT    f64 position [bench length unit], f64 force [bench force unit],
//                  f64 lab_time [s] (n triples for n actuators), u32 status (MeasurementStatus)
//   HEARTBEAT, HEARTBEAT_ACK, HOLD, HOLD_ACK, BYE   empty
//   ERROR          u16 code (ErrorCode), str limit, f64 value, f64 limit_value, str text
//
// A reply carries the sequence number of the request it answers.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "hybridtest/transfer/frame.h"
#include "hybridtest/transfer/safety.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer {

struct HelloMessage {
  std::uint16_t version = kProtocolVersion;
  std::string token;        // shared secret; empty when the server needs none
  std::string client_name;  // free text for the server's log
};

struct WelcomeMessage {
  std::uint16_t version = kProtocolVersion;
  std::string description;     // TransferSystem::Describe() of the served bench
  BenchUnits units;            // what COMMAND and MEASUREMENT values are expressed in
  SafetyLimits limits;         // the server's limits, SI (timeout is not sent)
  double heartbeat_timeout = 0.0;  // the server drops a silent client after this. Unit: [s].
  // Actuators of the served bench; sent as a trailing u16 only when > 1 (a one-actuator
  // WELCOME is unchanged).
  int actuators = 1;
};

enum class MeasurementStatus : std::uint32_t {
  kOk = 0,  // the bench reached the command and sampled
};

enum class ErrorCode : std::uint16_t {
  kProtocol = 1,       // malformed frame or message out of order
  kVersion = 2,        // unsupported protocol version in HELLO
  kAuth = 3,           // wrong or missing token
  kSafety = 4,         // command refused by the server's safety monitor; `limit` names it
  kBench = 5,          // the bench failed to execute the command
  kBusy = 6,           // another client holds the session
  kTimeout = 7,        // the client was silent longer than heartbeat_timeout
};
std::string ErrorCodeName(std::uint16_t code);

struct ErrorMessage {
  ErrorCode code = ErrorCode::kProtocol;
  std::string limit;          // kSafety: the SafetyStop limit name; otherwise empty
  double value = 0.0;         // kSafety: the offending value (SI)
  double limit_value = 0.0;   // kSafety: the limit value (SI)
  std::string text;           // human-readable explanation
};

Frame EncodeHello(std::uint32_t sequence, const HelloMessage& message);
Frame EncodeWelcome(std::uint32_t sequence, const WelcomeMessage& message);
Frame EncodeError(std::uint32_t sequence, const ErrorMessage& message);
// A bench of n actuators: COMMAND carries n f64 positions and MEASUREMENT n × (position,
// force, lab_time) then the u32 status (always MeasurementStatus::kOk).
Frame EncodeCommands(std::uint32_t sequence, std::span<const double> positions);
// Throws TransferError unless the payload holds n ≥ 1 values.
std::vector<double> DecodeCommands(const Frame& frame);
Frame EncodeMeasurements(std::uint32_t sequence, std::span<const Measurement> measurements);
// Throws TransferError unless the payload holds exactly `n` measurements and status OK.
std::vector<Measurement> DecodeMeasurements(const Frame& frame, int n);
// HEARTBEAT, HEARTBEAT_ACK, HOLD, HOLD_ACK, BYE.
Frame EncodeEmpty(MessageType type, std::uint32_t sequence);

// Decoders check the frame type and the exact payload length; they throw TransferError.
HelloMessage DecodeHello(const Frame& frame);
WelcomeMessage DecodeWelcome(const Frame& frame);
ErrorMessage DecodeError(const Frame& frame);
void DecodeEmpty(const Frame& frame, MessageType expected);

}  // namespace hybridtest::transfer
