// See server.h.
#include "hybridtest/transfer/openfresco/server.h"

#include <Eigen/Core>
#include <fmt/core.h>
#include <poll.h>

#include <chrono>
#include <cmath>
#include <cstring>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/handshake_queue.h"
#include "hybridtest/transfer/openfresco/server_session.h"

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

}  // namespace


Server::Server(TransferSystem& bench, ExpSetup setup, BenchServerOptions options)
    : bench_(bench),
      setup_(std::move(setup)),
      options_(CheckOptions(std::move(options))),
      bench_units_(bench.bench_units()),
      gate_(std::vector<SafetyLimits>(static_cast<std::size_t>(std::max(setup_.actuators, 1)),
                                      options_.limits)),
      listener_(options_.host, options_.port),
      handshakes_(options_.max_pending, options_.handshake_timeout, OpeningSize) {
  ValidateSetup(setup_);
  if (bench_.num_actuators() != setup_.actuators) {
    throw ConfigError(fmt::format("openfresco: the transform has {} rows, the bench moves {} "
                                  "actuators", setup_.actuators, bench_.num_actuators()));
  }
  for (int k = 0; k < gate_.size(); ++k) {
    const auto i = static_cast<std::size_t>(k);
    if (i < options_.start_positions.size()) {
      gate_.monitor(k).SetStartPosition(options_.start_positions[i]);
    } else if (options_.start_position) {
      gate_.monitor(k).SetStartPosition(*options_.start_position);
    }
  }
  const Eigen::MatrixXd setup_k =
      Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
          setup_.stiffness_matrix.data(), setup_.actuators, setup_.actuators);
  if (gate_.size() == 1) {
    // One actuator: its monitor predicts from its own secant, starting from K0.
    gate_.monitor(0).SetInitialStiffness(options_.initial_stiffness.value_or(setup_k(0, 0)));
  } else {
    // Several: the coupled force prediction with the options' matrix, else the setup's K_a.
    UseCoupledStiffness(gate_, options_.actuator_stiffness.value_or(setup_k));
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

}  // namespace hybridtest::transfer::openfresco
