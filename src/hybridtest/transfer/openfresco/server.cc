// See server.h.
#include "hybridtest/transfer/openfresco/server.h"

#include <fmt/core.h>
#include <poll.h>

#include <chrono>
#include <cmath>
#include <cstring>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/handshake_queue.h"

namespace hybridtest::transfer::openfresco {
namespace {

using Clock = std::chrono::steady_clock;
constexpr int kPollIntervalMs = 100;

// The bind policy of BenchServer (auth.h), positive timeouts, no test faults.
BenchServerOptions CheckOptions(BenchServerOptions options) {
  CheckBindPolicy(options.host, options.port, options.token, "the OpenFresco bench");
  if (!(options.heartbeat_timeout > 0.0) || !(options.send_timeout > 0.0) ||
      !(options.handshake_timeout > 0.0)) {
    throw ConfigError(fmt::format(
        "OpenFresco server: heartbeat_timeout = {} s, send_timeout = {} s, handshake_timeout = "
        "{} s: expected positive times", options.heartbeat_timeout, options.send_timeout,
        options.handshake_timeout));
  }
  if (!options.faults.empty()) {
    throw ConfigError("--inject: test faults are a facility of the hybridtest protocol; they "
                      "are not available with --protocol openfresco");
  }
  return options;
}

// True if the peer of `fd` has closed or reset its end, even with bytes still unread.
bool PeerHasLeft(int fd) {
  pollfd p{fd, POLLRDHUP, 0};
  if (poll(&p, 1, 0) < 0) return false;
  return (p.revents & (POLLRDHUP | POLLHUP | POLLERR)) != 0;
}

}  // namespace

struct Server::Session {
  Session(Socket socket, std::string peer_address)
      : client(std::move(socket)), peer(std::move(peer_address)) {}
  Socket client;
  std::string peer;                  // the client's address (auth throttle, logs)
  Header header;
  std::vector<double> trial_vel;     // last trial velocities (wire units), n or empty
  std::vector<double> trial_accel;   // last trial accelerations (wire units), n or empty
  bool measured = false;             // a trial has been executed in this session
  double offset = 0.0;               // measured position − p0. Unit: [m].
  std::vector<double> offsets, forces;  // several actuators: per actuator. Units: [m], [N].
  double force = 0.0;                // measured force. Unit: [N].
  double lab_time = 0.0;             // lab time of the measurement. Unit: [s].
};

Server::Server(TransferSystem& bench, ExpSetup setup, BenchServerOptions options)
    : bench_(bench),
      setup_(std::move(setup)),
      options_(CheckOptions(std::move(options))),
      bench_units_(bench.bench_units()),
      gate_(options_.limits),
      listener_(options_.host, options_.port),
      handshakes_(options_.max_pending, options_.handshake_timeout, OpeningSize) {
  ValidateSetup(setup_);
  if (options_.start_position) gate_.monitor().SetStartPosition(*options_.start_position);
  gate_.monitor().SetInitialStiffness(options_.initial_stiffness.value_or(setup_.initial_stiffness));
  if (setup_.actuators > 1) {
    ValidateMultiSetup(setup_);
    if (bench_.num_actuators() != setup_.actuators) {
      throw ConfigError(fmt::format("openfresco: the transform has {} rows, the bench moves {} "
                                    "actuators", setup_.actuators, bench_.num_actuators()));
    }
    const auto na = static_cast<std::size_t>(setup_.actuators);
    group_ = std::make_unique<SafetyGateGroup>(std::vector<SafetyLimits>(na, options_.limits));
    for (std::size_t k = 0; k < na && k < options_.start_positions.size(); ++k) {
      group_->monitor(static_cast<int>(k)).SetStartPosition(options_.start_positions[k]);
    }
  }
}

std::string Server::address() const { return listener_.address(); }

void Server::Log(const std::string& line) const {
  if (options_.log) options_.log(line);
}

void Server::HoldBench(const std::string& why) {
  bench_.Hold();
  bench_held_ = true;
  Log(fmt::format("holding: {}", why));
}

void Server::Serve() {
  bench_.Activate();
  Log(fmt::format("serving {} to OpenFresco clients on {} (n = {})", bench_.Describe(),
                  address(), setup_.dofs()));
  while (!stop_.load()) {
    ServeOpeningsTurn(
        listener_, handshakes_, kPollIntervalMs, stop_,
        [this](std::size_t i) { return AdvanceHandshake(i); },
        [this] { DropExpiredHandshakes(); },
        [this](const std::string& evicted) {
          Log(fmt::format("{} connections await their header: dropped the oldest, from {}",
                          options_.max_pending, evicted));
        });
  }
  handshakes_.TakeAll();
  HoldBench("server stopping");
  bench_.Deactivate();
  Log("stopped");
}

bool Server::AdvanceHandshake(std::size_t i) {
  std::vector<std::uint8_t> opening;
  HandshakeQueue::Progress progress = HandshakeQueue::Progress::kWaiting;
  try {
    progress = handshakes_.ReadOpening(i, opening);
  } catch (const TransferError& e) {
    const HandshakeQueue::Pending p = handshakes_.Take(i);
    Log(fmt::format("ERROR: {} (from {})", e.what(), p.peer));
    HoldBench("session not opened");
    return false;
  }
  if (progress == HandshakeQueue::Progress::kWaiting) return false;
  HandshakeQueue::Pending p = handshakes_.Take(i);
  if (progress == HandshakeQueue::Progress::kClosed) {
    Log(fmt::format("a connection from {} left before its header was complete ({} bytes)",
                    p.peer, p.bytes.size()));
    return false;
  }
  Session session(std::move(p.socket), p.peer);
  if (!OpenSession(session, opening)) {
    HoldBench("session not opened");
    return false;
  }
  // One session at a time: whoever else is waiting is closed.
  for (const HandshakeQueue::Pending& other : handshakes_.TakeAll()) {
    Log(fmt::format("refused a waiting connection from {}: one OpenFresco session at a time",
                    other.peer));
  }
  ++sessions_;
  ServeClient(session);
  return true;
}

void Server::DropExpiredHandshakes() {
  for (const HandshakeQueue::Pending& p : handshakes_.TakeExpired(Clock::now())) {
    Log(fmt::format("ERROR: incomplete header from {}: {} bytes of the opening arrived within "
                    "{} s of connecting (handshake timeout); closed",
                    p.peer, p.bytes.size(), options_.handshake_timeout));
  }
}

void Server::RefuseBusyClient() {
  Socket other = listener_.Accept(0.0);
  if (other.is_open()) {
    Log(fmt::format("refused a second client from {}: one OpenFresco session at a time",
                    PeerAddress(other.fd())));
  }
}

bool Server::Reply(Session& session, const std::vector<double>& values) {
  return SendAll(session.client.fd(), EncodeMessage(values, session.header.data_size),
                 options_.send_timeout);
}

void Server::ServeClient(Session& session) {
  const double timeout = options_.heartbeat_timeout;
  const std::size_t message_bytes = static_cast<std::size_t>(session.header.data_size) * 8;
  auto last_message = Clock::now();
  while (!stop_.load()) {
    pollfd fds[2] = {{session.client.fd(), POLLIN, 0}, {listener_.fd(), POLLIN, 0}};
    poll(fds, 2, kPollIntervalMs);
    if (fds[1].revents & POLLIN) RefuseBusyClient();
    if (fds[0].revents & (POLLIN | POLLHUP | POLLERR)) {
      std::vector<std::uint8_t> bytes(message_bytes);
      const ReadStatus status = ReadBytes(session.client.fd(), timeout, bytes);
      if (status == ReadStatus::kClosed) return HoldBench("client disconnected");
      if (status == ReadStatus::kTimeout) {
        Log(fmt::format("ERROR: incomplete message: {} bytes (dataSize {} × 8) did not arrive "
                        "within {} s", message_bytes, session.header.data_size, timeout));
        return HoldBench("client timed out mid-message");
      }
      last_message = Clock::now();
      if (!HandleMessage(session, DecodeMessage(bytes))) return;
      continue;
    }
    if (Clock::now() - last_message > std::chrono::duration<double>(timeout)) {
      Log(fmt::format("ERROR: no message for {} s (--heartbeat-timeout)", timeout));
      return HoldBench("client silent beyond the heartbeat timeout");
    }
  }
  HoldBench("server stopping");
}

bool Server::OpenSession(Session& session, const std::vector<std::uint8_t>& bytes) {
  Opening opening;
  try {
    opening = DecodeOpening(bytes);
  } catch (const TransferError& e) {
    Log(fmt::format("ERROR: {} (from {})", e.what(), session.peer));
    return false;
  }
  // The token rules of BenchServer (auth.h): constant-time comparison, lockout per address
  // block, a global budget of wrong tokens.
  const auto now = Clock::now();
  if (const auto verdict = auth_.Check(session.peer, now);
      verdict != AuthThrottle::Verdict::kAllowed) {
    Log("ERROR: " + AuthThrottle::RefusalText(verdict, session.peer));
    return false;
  }
  if (!TokensEqual(opening.token, options_.token)) {
    ++auth_failures_;
    if (auth_.RecordFailure(session.peer, now)) {
      Log(fmt::format("auth lockout: {} wrong tokens from block {} (last from {}); its sessions "
                      "are refused for {} s", AuthThrottle::kMaxFailures,
                      AddressBlock(session.peer), session.peer, AuthThrottle::kLockout.count()));
    }
    Log(opening.token.empty()
            ? fmt::format("ERROR: this bench requires a token and the client sent none (from "
                          "{}; the hybridtest token preamble; see docs/openfresco.md)",
                          session.peer)
            : fmt::format("ERROR: wrong token from {}: the client's token does not match the "
                          "bench's (--token-file / HYBRIDTEST_BENCH_TOKEN)", session.peer));
    return false;
  }
  auth_.RecordSuccess(session.peer);
  session.header = opening.header;
  try {
    ValidateHeader(session.header);
  } catch (const TransferError& e) {
    Log(fmt::format("ERROR: {}", e.what()));
    return false;
  }
  if (session.header.dofs() != setup_.dofs()) {
    Log(fmt::format("ERROR: the client's element has n = {} degrees of freedom, the setup's "
                    "transform has {} columns (openfresco.transform)",
                    session.header.dofs(), setup_.dofs()));
    return false;
  }
  Log(fmt::format("OpenFresco client connected from {}: n = {}, dataSize = {}", session.peer,
                  setup_.dofs(), session.header.data_size));
  return true;
}

bool Server::HandleMessage(Session& session, const std::vector<double>& message) {
  const int n = setup_.dofs();
  const int action = ActionOf(message);
  switch (action) {
    case static_cast<int>(Action::kSetTrialResponse):
      return HandleTrial(session, message);
    case static_cast<int>(Action::kCommitState):
      return true;
    case static_cast<int>(Action::kGetDaqResponse):
      return Reply(session, DaqResponse(session));
    case static_cast<int>(Action::kGetDisp):
      if (!session.measured) return Reply(session, std::vector<double>(n, 0.0));
      return Reply(session, group_ ? ElementDisplacementOf(setup_, session.offsets)
                                   : ElementDisplacement(setup_, session.offset));
    case static_cast<int>(Action::kGetVel):
      return Reply(session, session.trial_vel.empty()
                                ? std::vector<double>(n, 0.0)
                                : group_ ? ProjectOnActuators(setup_, session.trial_vel)
                                         : ProjectOnActuator(setup_, session.trial_vel));
    case static_cast<int>(Action::kGetAccel):
      return Reply(session, session.trial_accel.empty()
                                ? std::vector<double>(n, 0.0)
                                : group_ ? ProjectOnActuators(setup_, session.trial_accel)
                                         : ProjectOnActuator(setup_, session.trial_accel));
    case static_cast<int>(Action::kGetForce):
      if (group_) {
        return Reply(session, session.measured ? ElementForcesOf(setup_, session.forces)
                                               : std::vector<double>(n, 0.0));
      }
      return Reply(session, ElementForces(setup_, session.measured ? session.force : 0.0));
    case static_cast<int>(Action::kGetTime):
      return Reply(session, {session.lab_time});
    case static_cast<int>(Action::kGetInitialStiff):
    case static_cast<int>(Action::kGetTangentStiff):
      return Reply(session, group_ ? ElementStiffnessOf(setup_)
                                   : ElementStiffness(setup_, setup_.initial_stiffness));
    case static_cast<int>(Action::kGetDamp):
    case static_cast<int>(Action::kGetMass):
      return Reply(session, std::vector<double>(static_cast<std::size_t>(n) * n, 0.0));
    case static_cast<int>(Action::kShutdown):
      HoldBench("client sent shutdown (98)");
      return false;
    case static_cast<int>(Action::kDie):
      HoldBench("client ended the session (99)");
      return false;
    default:
      Log(fmt::format("ERROR: action {} ({}) is not served; expected 3, 5, 6, 7-15, 98 or 99",
                      message.empty() ? 0.0 : message[0], ActionName(action)));
      HoldBench("unknown action");
      return false;
  }
}

bool Server::HandleTrial(Session& session, const std::vector<double>& message) {
  const auto& size = session.header.size_ctrl;
  // A trial whose client is gone (it gave up waiting, or vanished) is stale: never executed.
  if (PeerHasLeft(session.client.fd())) {
    Log(fmt::format("ERROR: trial {} not executed: the client at {} has closed its connection "
                    "(a trial whose client is gone never moves the bench)", trials_.load() + 1,
                    session.peer));
    HoldBench("client left before its trial was executed");
    return false;
  }
  const long count = ++trials_;
  // [3 | d | v | a | force | time]: every value must be finite.
  const std::size_t used = 1 + static_cast<std::size_t>(size[0] + size[1] + size[2] + size[3] +
                                                        size[4]);
  for (std::size_t i = 1; i < used; ++i) {
    if (!std::isfinite(message[i])) {
      Log(fmt::format("ERROR: trial {}: word {} is {}; expected finite values", count, i,
                      message[i]));
      HoldBench("non-finite trial response");
      return false;
    }
  }
  const std::span<const double> words(message);
  const auto block = [&](int index) {
    std::size_t start = 1;
    for (int k = 0; k < index; ++k) start += static_cast<std::size_t>(size[k]);
    return std::vector<double>(words.begin() + static_cast<long>(start),
                               words.begin() + static_cast<long>(start + size[index]));
  };
  const std::vector<double> d = block(kDisp);
  session.trial_vel = size[kVel] == size[kDisp] ? block(kVel) : std::vector<double>();
  session.trial_accel = size[kAccel] == size[kDisp] ? block(kAccel) : std::vector<double>();
  // Check, move, check, as BenchServer does; a refusal or a bench failure ends the session.
  const double command = ActuatorCommand(setup_, d);  // [m]
  const double m_per_unit = bench_units_.metres_per_length_unit;
  const double n_per_unit = bench_units_.newtons_per_force_unit;
  const auto resume = [&] {
    if (bench_held_) {
      bench_.Activate();
      bench_held_ = false;
    }
  };
  try {
    if (group_) {  // every actuator, every command checked before any moves
      std::vector<GatedMove> moves;
      group_->Move(bench_, ActuatorCommands(setup_, d), {count, 0},
                   std::vector<double>(setup_.p0s.size(), 0.0), moves, resume);
      session.offsets.clear();
      session.forces.clear();
      for (std::size_t k = 0; k < moves.size(); ++k) {
        session.offsets.push_back(moves[k].position - setup_.p0s[k]);
        session.forces.push_back(moves[k].force);
      }
      session.measured = true;
      session.lab_time = moves[0].lab_time;
      return true;
    }
    GatedMove move;
    gate_.Move(bench_, command, {count, 0}, 0.0, move, [&] {
      if (bench_held_) {
        bench_.Activate();
        bench_held_ = false;
      }
    });
    const Measurement& m = move.raw;
    session.measured = true;
    session.offset = m.position * m_per_unit - setup_.p0;
    session.force = m.force * n_per_unit;
    session.lab_time = m.lab_time;
    return true;
  } catch (const SafetyStop& e) {
    Log(fmt::format("ERROR: safety refusal at trial {} ({}): {}", count, e.limit(), e.what()));
    HoldBench(fmt::format("safety refusal at trial {}", count));
  } catch (const Error& e) {
    Log(fmt::format("ERROR: the bench failed to execute trial {}: {}", count, e.what()));
    HoldBench(fmt::format("bench failure at trial {}", count));
  }
  return false;
}

std::vector<double> Server::DaqResponse(const Session& session) const {
  const auto& size = session.header.size_daq;
  const double first[5] = {
      session.offset / setup_.wire_units.metres_per_length_unit, 0.0, 0.0,
      session.force / setup_.wire_units.newtons_per_force_unit, session.lab_time};
  std::vector<double> out;
  for (int k = 0; k < 5; ++k) {
    for (int i = 0; i < size[k]; ++i) {
      double v = i == 0 && session.measured ? first[k] : 0.0;
      if (group_ && session.measured && k != 4) {  // several actuators: actuator i's value
        const auto a = static_cast<std::size_t>(i);
        v = k == 0 && a < session.offsets.size()
                ? session.offsets[a] / setup_.wire_units.metres_per_length_unit
            : k == 3 && a < session.forces.size()
                ? session.forces[a] / setup_.wire_units.newtons_per_force_unit
                : 0.0;
      }
      out.push_back(v);
    }
  }
  return out;
}

}  // namespace hybridtest::transfer::openfresco
