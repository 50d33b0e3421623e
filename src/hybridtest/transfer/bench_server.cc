#include "hybridtest/transfer/bench_server.h"

#include <fmt/core.h>
#include <poll.h>

#include <chrono>
#include <cmath>
#include <limits>

#include "hybridtest/common/error.h"
#include "hybridtest/common/text.h"
#include "hybridtest/transfer/protocol.h"

namespace hybridtest::transfer {
namespace {

using Clock = std::chrono::steady_clock;
constexpr int kPollIntervalMs = 100;

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

}  // namespace

struct BenchServer::Session {
  explicit Session(Socket socket, std::string peer_address = {})
      : client(std::move(socket)), peer(std::move(peer_address)) {}
  Socket client;
  std::string peer;                 // the client's address (for the auth throttle and logs)
  std::uint64_t last_sequence = 0;  // of the last request accepted; the next must be + 1
  bool refused = false;       // a safety refusal latched: every further COMMAND is refused
  std::string refused_limit;  // the limit of that refusal
  std::string refused_text;
};

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
      handshakes_(options_.max_pending, options_.handshake_timeout) {
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
  while (!stop_.load()) {
    ServeOpeningsTurn(
        listener_, handshakes_, kPollIntervalMs, stop_,
        [this](std::size_t i) { return AdvanceHandshake(i); },
        [this] { DropExpiredHandshakes(); },
        [this](const std::string& evicted) {
          Log(fmt::format("{} connections await HELLO: dropped the oldest, from {}",
                          options_.max_pending, evicted));
        });
  }
  handshakes_.TakeAll();
  HoldBench("server stopping");
  bench_.Deactivate();
  Log("stopped");
}

bool BenchServer::AdvanceHandshake(std::size_t i) {
  Frame hello;
  HandshakeQueue::Progress progress = HandshakeQueue::Progress::kWaiting;
  try {
    progress = handshakes_.Read(i, hello);
  } catch (const TransferError& e) {
    HandshakeQueue::Pending p = handshakes_.Take(i);
    Session rejected(std::move(p.socket), p.peer);
    SendError(rejected, 0, static_cast<int>(ErrorCode::kProtocol), "", 0, 0,
              fmt::format("expected HELLO: {}", e.what()));
    return false;
  }
  if (progress == HandshakeQueue::Progress::kWaiting) return false;
  HandshakeQueue::Pending p = handshakes_.Take(i);
  if (progress == HandshakeQueue::Progress::kClosed) {
    Log(fmt::format("a connection from {} left before HELLO", p.peer));
    return false;
  }
  Session session(std::move(p.socket), p.peer);
  if (!Handshake(session, hello)) return false;
  // One session at a time: whoever else is waiting is told the bench is busy.
  for (HandshakeQueue::Pending& other : handshakes_.TakeAll()) {
    Session busy(std::move(other.socket), other.peer);
    SendError(busy, 0, static_cast<int>(ErrorCode::kBusy), "", 0, 0,
              "the bench is serving another client; try again when it has disconnected");
  }
  ServeSession(session);
  return true;
}

void BenchServer::DropExpiredHandshakes() {
  for (HandshakeQueue::Pending& p : handshakes_.TakeExpired(Clock::now())) {
    Session late(std::move(p.socket), p.peer);
    SendError(late, 0, static_cast<int>(ErrorCode::kTimeout), "", 0, 0,
              fmt::format("no complete HELLO within {} s of connecting (handshake timeout)",
                          options_.handshake_timeout));
  }
}

bool BenchServer::Send(Session& session, const Frame& frame) {
  return SendAll(session.client.fd(), EncodeFrame(frame), options_.send_timeout);
}

void BenchServer::SendError(Session& session, std::uint32_t sequence, int code,
                            const std::string& limit, double value, double limit_value,
                            const std::string& text) {
  ErrorMessage m;
  m.code = static_cast<ErrorCode>(code);
  m.limit = limit;
  m.value = value;
  m.limit_value = limit_value;
  m.text = text.size() > 4000 ? text.substr(0, 4000) : text;
  Log(fmt::format("ERROR {} (sequence {}): {}", ErrorCodeName(static_cast<std::uint16_t>(code)),
                  sequence, m.text));
  Send(session, EncodeError(sequence, m));
}

void BenchServer::RefuseBusyClient() {
  Session other(listener_.Accept(0.0));
  if (!other.client.is_open()) return;
  SendError(other, 0, static_cast<int>(ErrorCode::kBusy), "", 0, 0,
            "the bench is serving another client; try again when it has disconnected");
}

void BenchServer::ServeSession(Session& session) {
  const auto hold = [&](const std::string& why) { HoldBench(why); };
  const auto timeout = std::chrono::duration<double>(options_.heartbeat_timeout);
  auto last_frame = Clock::now();
  while (!stop_.load()) {
    pollfd fds[2] = {{session.client.fd(), POLLIN, 0}, {listener_.fd(), POLLIN, 0}};
    poll(fds, 2, kPollIntervalMs);
    if (fds[1].revents & POLLIN) RefuseBusyClient();
    if (fds[0].revents & (POLLIN | POLLHUP | POLLERR)) {
      Frame frame;
      ReadStatus status;
      try {
        status = ReadFrame(session.client.fd(), options_.heartbeat_timeout, frame);
      } catch (const TransferError& e) {
        SendError(session, 0, static_cast<int>(ErrorCode::kProtocol), "", 0, 0, e.what());
        return hold("protocol error");
      }
      if (status == ReadStatus::kClosed) return hold("client disconnected");
      if (status == ReadStatus::kTimeout) {
        SendError(session, 0, static_cast<int>(ErrorCode::kTimeout), "", 0, 0,
                  "incomplete frame: the rest did not arrive within the heartbeat timeout");
        return hold("client timed out mid-frame");
      }
      last_frame = Clock::now();
      // Strict sequence: each request takes the next number; anything else (a replay, a
      // stale or skipped number) is refused before it is decoded and ends the session.
      const std::uint64_t expected = session.last_sequence + 1;
      if (frame.sequence != expected) {
        SendError(session, frame.sequence, static_cast<int>(ErrorCode::kProtocol), "", 0, 0,
                  fmt::format("{} with sequence number {}: expected {} (each request takes the "
                              "next number); a duplicate or stale request is never executed",
                              MessageTypeName(static_cast<std::uint16_t>(frame.type)),
                              frame.sequence, expected));
        return hold("duplicate, stale or skipped sequence number");
      }
      session.last_sequence = frame.sequence;
      if (!HandleFrame(session, frame)) return hold("session ended");
      continue;
    }
    if (Clock::now() - last_frame > timeout) {
      SendError(session, 0, static_cast<int>(ErrorCode::kTimeout), "", 0, 0,
                fmt::format("no frame for {} s (heartbeat_timeout); send HEARTBEAT when idle",
                            options_.heartbeat_timeout));
      return hold("client silent beyond the heartbeat timeout");
    }
  }
  Send(session, EncodeEmpty(MessageType::kBye, 0));
  hold("server stopping");
}

bool BenchServer::Handshake(Session& session, const Frame& frame) {
  const auto auth = static_cast<int>(ErrorCode::kAuth);
  try {
    if (frame.type != MessageType::kHello) {
      throw TransferError(fmt::format("got {} before HELLO",
                                      MessageTypeName(static_cast<std::uint16_t>(frame.type))));
    }
    const HelloMessage hello = DecodeHello(frame);
    if (hello.version != kProtocolVersion) {
      SendError(session, frame.sequence, static_cast<int>(ErrorCode::kVersion), "", 0, 0,
                fmt::format("protocol version {} is not supported; this bench speaks {}",
                            hello.version, kProtocolVersion));
      return false;
    }
    const auto now = Clock::now();
    if (const auto verdict = auth_.Check(session.peer, now);
        verdict != AuthThrottle::Verdict::kAllowed) {
      SendError(session, frame.sequence, auth, "", 0, 0,
                AuthThrottle::RefusalText(verdict, session.peer));
      return false;
    }
    if (!TokensEqual(hello.token, options_.token)) {
      if (auth_.RecordFailure(session.peer, now)) {
        Log(fmt::format("auth lockout: {} wrong tokens from block {} (last from {}); its HELLOs "
                        "are refused for {} s", AuthThrottle::kMaxFailures,
                        AddressBlock(session.peer), session.peer,
                        AuthThrottle::kLockout.count()));
      }
      SendError(session, frame.sequence, auth, "", 0, 0,
                "wrong or missing token: the client's token does not match the bench's "
                "(--token-file / HYBRIDTEST_BENCH_TOKEN)");
      return false;
    }
    auth_.RecordSuccess(session.peer);
    WelcomeMessage welcome;
    welcome.description = bench_.Describe();
    welcome.units = units_;
    welcome.limits = options_.limits;
    welcome.heartbeat_timeout = options_.heartbeat_timeout;
    welcome.actuators = bench_.num_actuators();
    Log(fmt::format("client '{}' connected from {}", hello.client_name, session.peer));
    session.last_sequence = frame.sequence;
    return Send(session, EncodeWelcome(frame.sequence, welcome));
  } catch (const TransferError& e) {
    SendError(session, frame.sequence, static_cast<int>(ErrorCode::kProtocol), "", 0, 0,
              fmt::format("expected HELLO: {}", e.what()));
    return false;
  }
}

bool BenchServer::HandleFrame(Session& session, const Frame& frame) {
  try {
    switch (frame.type) {
      case MessageType::kCommand:
        return HandleCommand(session, frame);
      case MessageType::kHeartbeat:
        DecodeEmpty(frame, MessageType::kHeartbeat);
        return Send(session, EncodeEmpty(MessageType::kHeartbeatAck, frame.sequence));
      case MessageType::kHold:
        DecodeEmpty(frame, MessageType::kHold);
        HoldBench("client asked for HOLD");
        return Send(session, EncodeEmpty(MessageType::kHoldAck, frame.sequence));
      case MessageType::kRead:  // where the actuators are, nothing moves (the start check)
        DecodeEmpty(frame, MessageType::kRead);
        if (const auto now = bench_.ReadAll()) {
          return Send(session, EncodeMeasurements(frame.sequence, *now));
        }
        SendError(session, frame.sequence, static_cast<int>(ErrorCode::kBench), "", 0, 0,
                  "this bench cannot read its position without moving");
        return true;
      case MessageType::kBye:
        HoldBench("client said BYE");
        Send(session, EncodeEmpty(MessageType::kBye, frame.sequence));
        return false;
      default:
        SendError(session, frame.sequence, static_cast<int>(ErrorCode::kProtocol), "", 0, 0,
                  fmt::format("unexpected {} frame from a client in session",
                              MessageTypeName(static_cast<std::uint16_t>(frame.type))));
        return false;
    }
  } catch (const TransferError& e) {
    SendError(session, frame.sequence, static_cast<int>(ErrorCode::kProtocol), "", 0, 0,
              e.what());
    return false;
  }
}

// Called from a catch block after a failed gated move: a safety refusal holds the bench,
// latches the refusal and answers ERROR safety (the session goes on); a bench failure holds
// and answers ERROR bench (the session ends).
bool BenchServer::AnswerFailedMove(Session& session, const Frame& frame, long n) {
  try {
    throw;
  } catch (const SafetyStop& e) {
    HoldBench(fmt::format("safety refusal at command {} ({})", n, e.limit()));
    session.refused = true;
    session.refused_limit = e.limit();
    session.refused_text = e.what();
    SendError(session, frame.sequence, static_cast<int>(ErrorCode::kSafety), e.limit(),
              e.value(), e.limit_value(), e.what());
    return true;
  } catch (const Error& e) {
    HoldBench(fmt::format("bench failure at command {}", n));
    SendError(session, frame.sequence, static_cast<int>(ErrorCode::kBench), "", 0, 0,
              fmt::format("the bench failed to execute command {}: {}", n, e.what()));
    return false;
  }
}

bool BenchServer::HandleCommand(Session& session, const Frame& frame) {
  // One position per actuator; a COMMAND of another count is not received (nothing moves).
  const std::vector<double> commands = DecodeCommands(frame);
  if (static_cast<int>(commands.size()) != gate_.size()) {
    SendError(session, frame.sequence, static_cast<int>(ErrorCode::kProtocol), "", 0, 0,
              fmt::format("COMMAND with {} positions for a bench of {} actuators; send one per "
                          "actuator", commands.size(), gate_.size()));
    return false;
  }
  const long n = ++commands_received_;
  const auto fault = [&](FaultKind kind) { return HasFault(options_.faults, kind, n); };
  const auto safety = static_cast<int>(ErrorCode::kSafety);

  // Latched refusal: nothing moves until the client reconnects.
  if (session.refused) {
    SendError(session, frame.sequence, safety, session.refused_limit, commands[0], 0,
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
    return AnswerFailedMove(session, frame, n);
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
    if (!SendAll(session.client.fd(), again, options_.send_timeout)) return false;
  }
  previous_measurement_ = clean;
  return SendAll(session.client.fd(), bytes, options_.send_timeout);
}

}  // namespace hybridtest::transfer
