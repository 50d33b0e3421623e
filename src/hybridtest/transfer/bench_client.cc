#include "hybridtest/transfer/bench_client.h"

#include <fmt/core.h>

#include <chrono>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/limits_check.h"
#include "hybridtest/transfer/safety.h"

namespace hybridtest::transfer {

BenchClient::BenchClient(BenchClientOptions options) : options_(std::move(options)) {
  if (!(options_.connect_timeout > 0.0) || !(options_.reply_timeout > 0.0) ||
      !(options_.hold_timeout > 0.0)) {
    throw ConfigError(fmt::format(
        "bench client: connect_timeout = {} s, reply_timeout = {} s, hold_timeout = {} s: "
        "expected positive times",
        options_.connect_timeout, options_.reply_timeout, options_.hold_timeout));
  }
}

BenchClient::~BenchClient() = default;

std::string BenchClient::Endpoint() const {
  const bool v6 = options_.host.find(':') != std::string::npos;
  return v6 ? fmt::format("[{}]:{}", options_.host, options_.port)
            : fmt::format("{}:{}", options_.host, options_.port);
}

void BenchClient::Fail(const std::string& message) {
  socket_.Close();
  throw TransferError(message);
}

Frame BenchClient::Exchange(const Frame& frame, MessageType expected,
                            const std::string& waiting_for, double timeout) {
  if (!socket_.is_open()) {
    throw TransferError(fmt::format(
        "not connected to the bench at {} (needed for {}); call Activate() first, or again "
        "after a lost connection",
        Endpoint(), waiting_for));
  }
  if (!SendAll(socket_.fd(), EncodeFrame(frame), timeout)) {
    Fail(fmt::format("connection to the bench at {} was lost while sending the request for {}",
                     Endpoint(), waiting_for));
  }
  Frame reply;
  ReadStatus status = ReadStatus::kClosed;
  try {
    status = ReadFrame(socket_.fd(), timeout, reply);
  } catch (const TransferError& e) {
    Fail(fmt::format("the bench at {} sent a corrupted frame while we waited for {}: {}",
                     Endpoint(), waiting_for, e.what()));
  }
  if (status == ReadStatus::kClosed) {
    Fail(fmt::format("connection to the bench at {} was lost while waiting for {}", Endpoint(),
                     waiting_for));
  }
  if (status == ReadStatus::kTimeout) {
    Fail(fmt::format("the bench at {} did not answer within {} s while we waited for {}; "
                     "the connection was closed so the bench holds",
                     Endpoint(), timeout, waiting_for));
  }
  if (reply.type == MessageType::kError) {
    ErrorMessage error;
    try {
      error = DecodeError(reply);
    } catch (const TransferError& e) {
      Fail(fmt::format("the bench at {} sent a malformed ERROR while we waited for {}: {}",
                       Endpoint(), waiting_for, e.what()));
    }
    if (error.code == ErrorCode::kSafety) {
      throw SafetyStop(error.limit, error.value, error.limit_value, -1, -1, {},
                       fmt::format("the bench at {} refused {}: {}", Endpoint(), waiting_for,
                                   error.text));
    }
    Fail(fmt::format("the bench at {} answered ERROR {} while we waited for {}: {}", Endpoint(),
                     ErrorCodeName(static_cast<std::uint16_t>(error.code)), waiting_for,
                     error.text));
  }
  if (reply.sequence != frame.sequence) {
    Fail(fmt::format(
        "{} sequence number from the bench at {}: received {} with sequence {}, expected {} "
        "while waiting for {}",
        reply.sequence < frame.sequence ? "stale or duplicate" : "unexpected", Endpoint(),
        MessageTypeName(static_cast<std::uint16_t>(reply.type)), reply.sequence, frame.sequence,
        waiting_for));
  }
  if (reply.type != expected) {
    Fail(fmt::format("the bench at {} answered {} while we waited for {} ({} expected)",
                     Endpoint(), MessageTypeName(static_cast<std::uint16_t>(reply.type)),
                     waiting_for, MessageTypeName(static_cast<std::uint16_t>(expected))));
  }
  return reply;
}

void BenchClient::Activate() {
  // Activate() again after a Hold() (a monitor's Continue): the session is still open and the
  // bench resumes at the next COMMAND. A heartbeat checks that the server has not dropped it
  // meanwhile (a hold longer than its heartbeat_timeout); if it has, connect anew.
  if (socket_.is_open() && welcome_) {
    try {
      Heartbeat();
      return;
    } catch (const TransferError&) {
      socket_.Close();
    }
  }
  try {
    socket_ = ConnectTcp(options_.host, options_.port, options_.connect_timeout);
  } catch (const TransferError& e) {
    throw TransferError(fmt::format("{} (hybridtest bench protocol); is `hybridtest bench` "
                                    "running there?", e.what()));
  }
  HelloMessage hello;
  hello.token = options_.token;
  hello.client_name = options_.client_name;
  const Frame reply = Exchange(EncodeHello(next_sequence_++, hello), MessageType::kWelcome,
                               "WELCOME (the answer to HELLO)", options_.reply_timeout);
  try {
    WelcomeMessage welcome = DecodeWelcome(reply);
    if (welcome.version != kProtocolVersion) {
      Fail(fmt::format("the bench at {} speaks protocol version {}, this client {}", Endpoint(),
                       welcome.version, kProtocolVersion));
    }
    welcome_ = std::move(welcome);
  } catch (const TransferError& e) {
    Fail(fmt::format("bad WELCOME from the bench at {}: {}", Endpoint(), e.what()));
  }
  if (options_.expected_limits) {
    try {
      CheckLimitsAgainstBench(*options_.expected_limits, welcome_->limits, options_.limits_where,
                              fmt::format("the bench at {}", Endpoint()));
    } catch (const ConfigError&) {
      Hold();  // nothing moved; leave the session cleanly, then report
      socket_.Close();
      throw;
    }
  }
}

BenchAnnouncement BenchClient::Announce() const {
  if (!welcome_) return {};
  // WELCOME carries one set of limits, its first actuator's: announced for a bench of one.
  if (num_actuators() != 1) return {{}, "the bench at " + Endpoint()};
  return {{{std::nullopt, welcome_->limits}}, "the bench at " + Endpoint()};
}

void BenchClient::Execute(std::span<const double> commands, std::span<Measurement> out) {
  if (static_cast<int>(commands.size()) != num_actuators() || out.size() != commands.size()) {
    Fail(fmt::format("{} commands for the {} actuators of the bench at {}", commands.size(),
                     num_actuators(), Endpoint()));
  }
  const std::uint32_t sequence = next_sequence_++;
  const std::string what =
      commands.size() == 1
          ? fmt::format("the measurement of COMMAND sequence {} (position {} {})", sequence,
                        commands[0], bench_units().length_name)
          : fmt::format("the measurement of COMMAND sequence {} ({} actuators)", sequence,
                        commands.size());
  const Frame reply = Exchange(EncodeCommands(sequence, commands), MessageType::kMeasurement, what,
                               options_.reply_timeout);
  std::vector<Measurement> measured;
  try {
    measured = DecodeMeasurements(reply, num_actuators());
  } catch (const TransferError& e) {
    Fail(fmt::format("bad MEASUREMENT from the bench at {} for command {}: {}", Endpoint(),
                     sequence, e.what()));
  }
  for (std::size_t k = 0; k < out.size(); ++k) out[k] = measured[k];
}

void BenchClient::Hold() noexcept {
  try {
    if (!socket_.is_open()) return;
    Exchange(EncodeEmpty(MessageType::kHold, next_sequence_++), MessageType::kHoldAck,
             "HOLD_ACK", options_.hold_timeout);
  } catch (...) {
    // Best effort: if the HOLD did not get through, the connection is closed by now and the
    // server holds the bench on the disconnect.
    socket_.Close();
  }
}

void BenchClient::Heartbeat() {
  Exchange(EncodeEmpty(MessageType::kHeartbeat, next_sequence_++), MessageType::kHeartbeatAck,
           "HEARTBEAT_ACK", options_.reply_timeout);
}

std::optional<std::vector<Measurement>> BenchClient::ReadAll() {
  if (!socket_.is_open() || !welcome_) return std::nullopt;
  // Reading moves nothing, but it is an exchange on the connection.
  try {
    const Frame reply =
        Exchange(EncodeEmpty(MessageType::kRead, next_sequence_++), MessageType::kMeasurement,
                 "MEASUREMENT (the answer to READ)", options_.reply_timeout);
    return DecodeMeasurements(reply, num_actuators());
  } catch (const std::exception&) {
    // A server that cannot read (or an older one that does not know READ and closed the
    // session): connect again as before, and tell that nothing was read.
    try {
      if (!socket_.is_open()) Activate();
    } catch (const std::exception&) {
      // The next command reports the lost bench.
    }
    return std::nullopt;
  }
}

void BenchClient::Deactivate() {
  if (!socket_.is_open()) return;
  Exchange(EncodeEmpty(MessageType::kHold, next_sequence_++), MessageType::kHoldAck,
           "HOLD_ACK", options_.reply_timeout);
  Exchange(EncodeEmpty(MessageType::kBye, next_sequence_++), MessageType::kBye, "BYE",
           options_.reply_timeout);
  socket_.Close();
}

BenchUnits BenchClient::bench_units() const {
  return welcome_ ? welcome_->units : BenchUnits{};
}

std::string BenchClient::Describe() const {
  if (!welcome_) return fmt::format("remote bench at {} (not connected)", Endpoint());
  return fmt::format("remote bench at {}: {}", Endpoint(), welcome_->description);
}

}  // namespace hybridtest::transfer
