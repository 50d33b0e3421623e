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
  if (!(options.heartbeat_timeout > 0.0) || !(options.send_timeout > 0.0)) {
    throw ConfigError(fmt::format(
        "OpenFresco server: heartbeat_timeout = {} s, send_timeout = {} s: expected positive "
        "times", options.heartbeat_timeout, options.send_timeout));
  }
  if (!options.faults.empty()) {
    throw ConfigError("--inject: test faults are a facility of the hybridtest protocol; they "
                      "are not available with --protocol openfresco");
  }
  return options;
}

std::int32_t Int32At(const std::vector<std::uint8_t>& bytes, std::size_t at) {
  std::int32_t v = 0;
  std::memcpy(&v, bytes.data() + at, 4);
  return v;
}

}  // namespace

struct Server::Session {
  explicit Session(Socket socket) : client(std::move(socket)) {}
  Socket client;
  Header header;
  std::vector<double> trial_vel;     // last trial velocities (wire units), n or empty
  std::vector<double> trial_accel;   // last trial accelerations (wire units), n or empty
  bool measured = false;             // a trial has been executed in this session
  double offset = 0.0;               // measured position − p0. Unit: [m].
  double force = 0.0;                // measured force. Unit: [N].
  double lab_time = 0.0;             // lab time of the measurement. Unit: [s].
};

Server::Server(TransferSystem& bench, ExpSetup setup, BenchServerOptions options)
    : bench_(bench),
      setup_(std::move(setup)),
      options_(CheckOptions(std::move(options))),
      bench_units_(bench.bench_units()),
      monitor_(options_.limits),
      listener_(options_.host, options_.port) {
  ValidateSetup(setup_);
  if (options_.start_position) monitor_.SetStartPosition(*options_.start_position);
  monitor_.SetInitialStiffness(options_.initial_stiffness.value_or(setup_.initial_stiffness));
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
    Socket client = listener_.Accept(kPollIntervalMs * 1e-3);
    if (client.is_open()) ServeClient(std::move(client));
  }
  HoldBench("server stopping");
  bench_.Deactivate();
  Log("stopped");
}

void Server::RefuseBusyClient() {
  Socket other = listener_.Accept(0.0);
  if (other.is_open()) Log("refused a second client: one OpenFresco session at a time");
}

bool Server::Reply(Session& session, const std::vector<double>& values) {
  return SendAll(session.client.fd(), EncodeMessage(values, session.header.data_size),
                 options_.send_timeout);
}

void Server::ServeClient(Socket client) {
  Session session(std::move(client));
  ++sessions_;
  if (!OpenSession(session)) return HoldBench("session not opened");
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

bool Server::OpenSession(Session& session) {
  const int fd = session.client.fd();
  const double timeout = options_.heartbeat_timeout;
  // The first word tells the token preamble from the header.
  std::vector<std::uint8_t> bytes(4);
  if (ReadBytes(fd, timeout, bytes) != ReadStatus::kFrame) {
    Log("ERROR: the client left or stayed silent before sending its header");
    return false;
  }
  std::string token;
  if (Int32At(bytes, 0) == kTokenMagic) {
    std::vector<std::uint8_t> length(4);
    if (ReadBytes(fd, timeout, length) != ReadStatus::kFrame) {
      Log("ERROR: incomplete token preamble");
      return false;
    }
    const std::int32_t n = Int32At(length, 0);
    if (n < 1 || n > kMaxTokenBytes) {
      Log(fmt::format("ERROR: token preamble announces {} bytes; expected 1 to {}", n,
                      kMaxTokenBytes));
      return false;
    }
    std::vector<std::uint8_t> text(static_cast<std::size_t>(n));
    if (ReadBytes(fd, timeout, text) != ReadStatus::kFrame) {
      Log("ERROR: incomplete token preamble");
      return false;
    }
    token.assign(text.begin(), text.end());
    bytes.assign(4, 0);
    if (ReadBytes(fd, timeout, bytes) != ReadStatus::kFrame) {
      Log("ERROR: the client left or stayed silent before sending its header");
      return false;
    }
  }
  // The token rules of BenchServer (auth.h): constant-time comparison, lockout per address.
  const std::string peer = PeerAddress(fd);
  const auto now = Clock::now();
  if (auth_.IsLocked(peer, now)) {
    Log(fmt::format("ERROR: too many wrong tokens from {}: locked out for {} s after the last "
                    "one", peer, AuthThrottle::kLockout.count()));
    return false;
  }
  if (!TokensEqual(token, options_.token)) {
    if (auth_.RecordFailure(peer, now)) {
      Log(fmt::format("auth lockout: {} wrong tokens from {}; its sessions are refused for {} s",
                      AuthThrottle::kMaxFailures, peer, AuthThrottle::kLockout.count()));
    }
    Log(token.empty() ? "ERROR: this bench requires a token and the client sent none (the "
                        "hybridtest token preamble; see docs/openfresco.md)"
                      : "ERROR: wrong token: the client's token does not match the bench's "
                        "(--token / HYBRIDTEST_BENCH_TOKEN)");
    return false;
  }
  auth_.RecordSuccess(peer);
  // The rest of the 11-int header.
  bytes.resize(kHeaderBytes);
  std::vector<std::uint8_t> rest(kHeaderBytes - 4);
  if (ReadBytes(fd, timeout, rest) != ReadStatus::kFrame) {
    Log(fmt::format("ERROR: incomplete header: the 44 bytes did not arrive within {} s",
                    timeout));
    return false;
  }
  std::copy(rest.begin(), rest.end(), bytes.begin() + 4);
  try {
    session.header = DecodeHeader(bytes);
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
  Log(fmt::format("OpenFresco client connected: n = {}, dataSize = {}", setup_.dofs(),
                  session.header.data_size));
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
      return Reply(session, session.measured ? ElementDisplacement(setup_, session.offset)
                                             : std::vector<double>(n, 0.0));
    case static_cast<int>(Action::kGetVel):
      return Reply(session, session.trial_vel.empty()
                                ? std::vector<double>(n, 0.0)
                                : ProjectOnActuator(setup_, session.trial_vel));
    case static_cast<int>(Action::kGetAccel):
      return Reply(session, session.trial_accel.empty()
                                ? std::vector<double>(n, 0.0)
                                : ProjectOnActuator(setup_, session.trial_accel));
    case static_cast<int>(Action::kGetForce):
      return Reply(session, ElementForces(setup_, session.measured ? session.force : 0.0));
    case static_cast<int>(Action::kGetTime):
      return Reply(session, {session.lab_time});
    case static_cast<int>(Action::kGetInitialStiff):
    case static_cast<int>(Action::kGetTangentStiff):
      return Reply(session, ElementStiffness(setup_, setup_.initial_stiffness));
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
  try {
    monitor_.CheckCommand(command, count, 0);
    if (bench_held_) {
      bench_.Activate();
      bench_held_ = false;
    }
    const Measurement m = bench_.Execute(command / m_per_unit);
    monitor_.CheckMeasurement(command, m.position * m_per_unit, m.force * n_per_unit, count, 0);
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
    for (int i = 0; i < size[k]; ++i) out.push_back(i == 0 && session.measured ? first[k] : 0.0);
  }
  return out;
}

}  // namespace hybridtest::transfer::openfresco
