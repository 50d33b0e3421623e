#include "hybridtest/transfer/bench_server.h"

#include <fmt/core.h>

#include <chrono>
#include <cmath>
#include <limits>

#include "hybridtest/common/error.h"
#include "hybridtest/common/text.h"
#include "hybridtest/transfer/frame_replies.h"
#include "hybridtest/transfer/protocol.h"

namespace hybridtest::transfer {
namespace {

using Clock = std::chrono::steady_clock;

// The bind policy (auth.h) and positive timeouts.
const std::string& CheckOptions(const BenchServerOptions& options) {
  CheckBindPolicy(options.host, options.port, options.token, "the bench");
  if (!(options.heartbeat_timeout > 0.0) || !(options.send_timeout > 0.0) ||
      !(options.handshake_timeout > 0.0)) {
    throw ConfigError(fmt::format(
        "bench server: heartbeat_timeout = {} s, send_timeout = {} s, handshake_timeout = {} s: "
        "expected positive times",
        options.heartbeat_timeout, options.send_timeout, options.handshake_timeout));
  }
  return options.host;
}

// The codec for the ServerLoop: a frame is its header, the payload it announces and the CRC.
std::size_t MeasureFrame(const ServerLoop::Connection&, std::span<const std::uint8_t> bytes) {
  return FrameSize(bytes);
}

}  // namespace

void SetStartPositions(SafetyGate& gate, const BenchServerOptions& options) {
  for (int k = 0; k < gate.size(); ++k) {
    const auto i = static_cast<std::size_t>(k);
    if (i < options.start_positions.size()) {
      gate.monitor(k).SetStartPosition(options.start_positions[i]);
    } else if (options.start_position) {
      gate.monitor(k).SetStartPosition(*options.start_position);
    }
  }
}

BenchServer::BenchServer(TransferSystem& bench, BenchServerOptions options)
    : bench_(bench),
      options_(std::move(options)),
      units_(bench.bench_units()),
      gate_(std::vector<SafetyLimits>(static_cast<std::size_t>(bench.num_actuators()),
                                      options_.limits)),
      listener_(CheckOptions(options_), options_.port),
      loop_(listener_,
            {.max_connections = options_.max_connections,
             .max_frame_bytes = kFrameHeaderSize + kMaxPayloadLength + kFrameTrailerSize,
             .max_opening_bytes = kFrameHeaderSize + kMaxHelloPayload + kFrameTrailerSize,
             .handshake_timeout = options_.handshake_timeout,
             .frame_timeout = options_.heartbeat_timeout,
             .idle_timeout = options_.heartbeat_timeout,
             .send_timeout = options_.send_timeout},
            MeasureFrame,
            {.opened = [this](Connection& c) { return sessions_.try_emplace(c.id).second; },
             .frame = [this](Connection& c, std::span<const std::uint8_t> bytes) {
               return HandleBytes(c, bytes);
             },
             .closed = [this](Connection& c, const ServerLoop::Closing& closing) {
               Closed(c, closing);
             }},
            [this](const std::string& line) { Log(line); }) {
  SetStartPositions(gate_, options_);
  for (int k = 0; k < gate_.size(); ++k) {
    if (options_.initial_stiffness) gate_.monitor(k).SetInitialStiffness(*options_.initial_stiffness);
  }
  if (options_.actuator_stiffness) UseCoupledStiffness(gate_, *options_.actuator_stiffness);
}

std::string BenchServer::address() const { return listener_.address(); }

void BenchServer::Log(const std::string& line) const {
  // Client-supplied text (names, error texts) may hold newlines: one event, one line.
  if (options_.log) options_.log(Printable(line));
}

void BenchServer::HoldBench(const std::string& why) {
  bench_.Hold();
  bench_held_ = true;
  Log(fmt::format("holding: {}", why));
}

void BenchServer::Serve() {
  bench_.Activate();
  Log(fmt::format("serving {} on {}", bench_.Describe(), address()));
  loop_.Serve(stop_);
  HoldBench("server stopping");
  bench_.Deactivate();
  Log("stopped");
}

bool BenchServer::Send(Connection& c, const Frame& frame) { return SendFrameOn(loop_, c, frame); }

void BenchServer::SendError(Connection& c, std::uint32_t sequence, int code,
                            const std::string& limit, double value, double limit_value,
                            const std::string& text) {
  SendErrorOn(loop_, c, sequence, {static_cast<ErrorCode>(code), limit, value, limit_value, text},
              [this](const std::string& line) { Log(line); });
}

bool BenchServer::HandleBytes(Connection& c, std::span<const std::uint8_t> bytes) {
  Session& session = sessions_[c.id];
  Frame frame;
  try {
    frame = DecodeFrame(bytes);
  } catch (const TransferError& e) {
    SendError(c, 0, static_cast<int>(ErrorCode::kProtocol), "", 0, 0,
              c.established ? std::string(e.what()) : fmt::format("expected HELLO: {}", e.what()));
    session.end = "protocol error";
    return false;
  }
  if (!c.established) {
    c.established = Handshake(c, session, frame);
    return c.established;
  }
  // Strict sequence: each request takes the next number; anything else (a replay, a stale or
  // skipped number) is refused before it is decoded and ends the session.
  const std::uint64_t expected = session.last_sequence + 1;
  if (frame.sequence != expected) {
    SendError(c, frame.sequence, static_cast<int>(ErrorCode::kProtocol), "", 0, 0,
              fmt::format("{} with sequence number {}: expected {} (each request takes the next "
                          "number); a duplicate or stale request is never executed",
                          MessageTypeName(static_cast<std::uint16_t>(frame.type)),
                          frame.sequence, expected));
    session.end = "duplicate, stale or skipped sequence number";
    return false;
  }
  session.last_sequence = frame.sequence;
  return HandleFrame(c, session, frame);
}

void BenchServer::Closed(Connection& c, const ServerLoop::Closing& closing) {
  const auto timeout = static_cast<int>(ErrorCode::kTimeout);
  const auto protocol = static_cast<int>(ErrorCode::kProtocol);
  std::string hold;  // why the bench holds (a session ended); empty: it does not
  switch (closing.cause) {
    case CloseCause::kPeerLeft:
      if (c.established) {
        hold = "client disconnected";
      } else {
        Log(fmt::format("a connection from {} left before HELLO", c.peer));
      }
      break;
    case CloseCause::kHandshakeTimeout:
      SendError(c, 0, timeout, "", 0, 0,
                fmt::format("no complete HELLO within {} s of connecting (handshake timeout)",
                            options_.handshake_timeout));
      break;
    case CloseCause::kFrameTimeout:
      SendError(c, 0, timeout, "", 0, 0, closing.why);
      hold = "client timed out mid-frame";
      break;
    case CloseCause::kIdleTimeout:
      SendError(c, 0, timeout, "", 0, 0,
                fmt::format("no frame for {} s (heartbeat_timeout); send HEARTBEAT when idle",
                            options_.heartbeat_timeout));
      hold = "client silent beyond the heartbeat timeout";
      break;
    case CloseCause::kGarbled:
    case CloseCause::kTooLong:
      SendError(c, 0, protocol, "", 0, 0,
                c.established ? closing.why : fmt::format("expected HELLO: {}", closing.why));
      hold = "protocol error";
      break;
    case CloseCause::kMakeRoom:
      SendError(c, 0, static_cast<int>(ErrorCode::kBusy), "", 0, 0, closing.why);
      Log(fmt::format("closed a connection from {}: {}", c.peer, closing.why));
      break;
    case CloseCause::kRefused:
      break;
    case CloseCause::kByHandler:
      hold = sessions_[c.id].end.empty() ? "session ended" : sessions_[c.id].end;
      break;
    case CloseCause::kStopping:
      if (c.established) Send(c, EncodeEmpty(MessageType::kBye, 0));
      break;
  }
  // A reader's end never holds the bench another client commands.
  if (!hold.empty() && c.established && !closing.another_commands) HoldBench(hold);
  sessions_.erase(c.id);
}

bool BenchServer::Commands(Connection& c, const Frame& frame) {
  if (loop_.Claim(c.id)) return true;
  SendError(c, frame.sequence, static_cast<int>(ErrorCode::kBusy), "", 0, 0,
            fmt::format("another client (connection {}) commands the bench; this session may "
                        "READ and HEARTBEAT only; try again when it has disconnected",
                        loop_.commander()));
  return false;
}

bool BenchServer::Handshake(Connection& c, Session& session, const Frame& frame) {
  const auto auth = static_cast<int>(ErrorCode::kAuth);
  try {
    if (frame.type != MessageType::kHello) {
      throw TransferError(fmt::format("got {} before HELLO",
                                      MessageTypeName(static_cast<std::uint16_t>(frame.type))));
    }
    const HelloMessage hello = DecodeHello(frame);
    if (hello.version != kProtocolVersion) {
      SendError(c, frame.sequence, static_cast<int>(ErrorCode::kVersion), "", 0, 0,
                fmt::format("protocol version {} is not supported; this bench speaks {}",
                            hello.version, kProtocolVersion));
      return false;
    }
    const auto now = Clock::now();
    if (const auto verdict = auth_.Check(c.peer, now);
        verdict != AuthThrottle::Verdict::kAllowed) {
      SendError(c, frame.sequence, auth, "", 0, 0,
                AuthThrottle::RefusalText(verdict, c.peer));
      return false;
    }
    if (!TokensEqual(hello.token, options_.token)) {
      if (auth_.RecordFailure(c.peer, now)) {
        Log(fmt::format("auth lockout: {} wrong tokens from block {} (last from {}); its HELLOs "
                        "are refused for {} s", AuthThrottle::kMaxFailures,
                        AddressBlock(c.peer), c.peer,
                        AuthThrottle::kLockout.count()));
      }
      SendError(c, frame.sequence, auth, "", 0, 0,
                "wrong or missing token: the client's token does not match the bench's "
                "(--token-file / HYBRIDTEST_BENCH_TOKEN)");
      return false;
    }
    auth_.RecordSuccess(c.peer);
    WelcomeMessage welcome;
    welcome.description = bench_.Describe();
    welcome.units = units_;
    welcome.limits = options_.limits;
    welcome.heartbeat_timeout = options_.heartbeat_timeout;
    welcome.actuators = bench_.num_actuators();
    Log(fmt::format("client '{}' connected from {}", hello.client_name, c.peer));
    session.last_sequence = frame.sequence;
    return Send(c, EncodeWelcome(frame.sequence, welcome));
  } catch (const TransferError& e) {
    SendError(c, frame.sequence, static_cast<int>(ErrorCode::kProtocol), "", 0, 0,
              fmt::format("expected HELLO: {}", e.what()));
    return false;
  }
}

bool BenchServer::HandleFrame(Connection& c, Session& session, const Frame& frame) {
  try {
    switch (frame.type) {
      case MessageType::kCommand:
        return HandleCommand(c, session, frame);
      case MessageType::kHeartbeat:
        DecodeEmpty(frame, MessageType::kHeartbeat);
        return Send(c, EncodeEmpty(MessageType::kHeartbeatAck, frame.sequence));
      case MessageType::kHold:
        DecodeEmpty(frame, MessageType::kHold);
        if (!Commands(c, frame)) return true;  // a reader never holds the commander's run
        HoldBench("client asked for HOLD");
        return Send(c, EncodeEmpty(MessageType::kHoldAck, frame.sequence));
      case MessageType::kRead:  // where the actuators are, nothing moves (the start check)
        DecodeEmpty(frame, MessageType::kRead);
        if (const auto now = bench_.ReadAll()) {
          return Send(c, EncodeMeasurements(frame.sequence, *now));
        }
        SendError(c, frame.sequence, static_cast<int>(ErrorCode::kBench), "", 0, 0,
                  "this bench cannot read its position without moving");
        return true;
      case MessageType::kBye:
        if (loop_.commander() == 0 || loop_.commander() == c.id) {
          HoldBench("client said BYE");
        }
        Send(c, EncodeEmpty(MessageType::kBye, frame.sequence));
        return false;
      default:
        SendError(c, frame.sequence, static_cast<int>(ErrorCode::kProtocol), "", 0, 0,
                  fmt::format("unexpected {} frame from a client in session",
                              MessageTypeName(static_cast<std::uint16_t>(frame.type))));
        return false;
    }
  } catch (const TransferError& e) {
    SendError(c, frame.sequence, static_cast<int>(ErrorCode::kProtocol), "", 0, 0,
              e.what());
    return false;
  }
}

// Called from a catch block after a failed gated move: a safety refusal holds the bench,
// latches the refusal and answers ERROR safety (the session goes on); a bench failure holds
// and answers ERROR bench (the session ends).
bool BenchServer::AnswerFailedMove(Connection& c, Session& session, const Frame& frame,
                                   long n) {
  try {
    throw;
  } catch (const SafetyStop& e) {
    HoldBench(fmt::format("safety refusal at command {} ({})", n, e.limit()));
    session.refused = true;
    session.refused_limit = e.limit();
    session.refused_text = e.what();
    SendError(c, frame.sequence, static_cast<int>(ErrorCode::kSafety), e.limit(),
              e.value(), e.limit_value(), e.what());
    return true;
  } catch (const Error& e) {
    HoldBench(fmt::format("bench failure at command {}", n));
    SendError(c, frame.sequence, static_cast<int>(ErrorCode::kBench), "", 0, 0,
              fmt::format("the bench failed to execute command {}: {}", n, e.what()));
    return false;
  }
}

bool BenchServer::HandleCommand(Connection& c, Session& session, const Frame& frame) {
  // One position per actuator; a COMMAND of another count is not received (nothing moves).
  const std::vector<double> commands = DecodeCommands(frame);
  if (static_cast<int>(commands.size()) != gate_.size()) {
    SendError(c, frame.sequence, static_cast<int>(ErrorCode::kProtocol), "", 0, 0,
              fmt::format("COMMAND with {} positions for a bench of {} actuators; send one per "
                          "actuator", commands.size(), gate_.size()));
    return false;
  }
  if (!Commands(c, frame)) return true;  // nothing moves; the session may still read
  const long n = ++commands_received_;
  const auto fault = [&](FaultKind kind) { return HasFault(options_.faults, kind, n); };
  const auto safety = static_cast<int>(ErrorCode::kSafety);

  // Latched refusal: nothing moves until the client reconnects.
  if (session.refused) {
    SendError(c, frame.sequence, safety, session.refused_limit, commands[0], 0,
              "the bench is holding after a safety refusal (" + session.refused_text +
                  "); reconnect to resume");
    return true;
  }
  // Test faults that stop the answer before the bench moves.
  if (fault(FaultKind::kClose)) {
    Log(fmt::format("FAULT close at command {}", n));
    return false;
  }
  if (fault(FaultKind::kSilence)) {
    HoldBench(fmt::format("FAULT silence at command {}", n));
    return true;
  }
  // Check, move, check: every position before any actuator moves; a SafetyStop from any of
  // the three refuses and latches.
  try {
    gate_.MoveBench(bench_, commands, {n, 0}, moves_, [&] {
      if (bench_held_) {
        bench_.Activate();
        bench_held_ = false;
      }
    });
  } catch (const Error&) {
    return AnswerFailedMove(c, session, frame, n);
  }
  // Test faults on the answer.
  measured_.clear();
  for (const auto& m : moves_) {
    measured_.push_back(m.raw);
    ApplyMeasurementFaults(options_.faults, n, units_, measured_.back());
  }
  const std::uint32_t sequence =
      fault(FaultKind::kStaleSeq) ? frame.sequence - 1 : frame.sequence;
  std::vector<std::uint8_t> bytes = EncodeFrame(EncodeMeasurements(sequence, measured_));
  const std::vector<std::uint8_t> clean = bytes;
  if (fault(FaultKind::kCorrupt)) bytes[kFrameHeaderSize] ^= 0xFF;
  if (fault(FaultKind::kDuplicate)) {
    const auto& again = previous_measurement_.empty() ? clean : previous_measurement_;
    if (!loop_.Send(c, again)) return false;
  }
  previous_measurement_ = clean;
  return loop_.Send(c, bytes);
}

}  // namespace hybridtest::transfer
