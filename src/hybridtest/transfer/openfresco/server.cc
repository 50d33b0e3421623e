// See server.h.
#include "hybridtest/transfer/openfresco/server.h"

#include <Eigen/Core>
#include <fmt/core.h>

#include <chrono>
#include <cmath>
#include <cstring>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/openfresco/server_session.h"
#include "hybridtest/transfer/openfresco/wire.h"

namespace hybridtest::transfer::openfresco {
namespace {

using Clock = std::chrono::steady_clock;

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
      loop_(listener_,
            {.max_connections = options_.max_connections,
             .max_frame_bytes = static_cast<std::size_t>(kMaxDataSize) * 8,
             .max_opening_bytes = 8 + kMaxTokenBytes + kHeaderBytes,
             .handshake_timeout = options_.handshake_timeout,
             .frame_timeout = options_.heartbeat_timeout,
             .idle_timeout = options_.heartbeat_timeout,
             .send_timeout = options_.send_timeout},
            [this](const Connection& c, std::span<const std::uint8_t> bytes) {
              return Measure(c, bytes);
            },
            {.opened =
                 [this](Connection& c) {
                   if (loop_.commander() == 0) return true;
                   Log(fmt::format("refused a second client from {}: one OpenFresco session at "
                                   "a time", c.peer));
                   return false;
                 },
             .frame = [this](Connection& c, std::span<const std::uint8_t> bytes) {
               return HandleBytes(c, bytes);
             },
             .closed = [this](Connection& c, const ServerLoop::Closing& closing) {
               Closed(c, closing);
             }},
            [this](const std::string& line) { Log(line); }) {
  ValidateSetup(setup_);
  if (bench_.num_actuators() != setup_.actuators) {
    throw ConfigError(fmt::format("openfresco: the transform has {} rows, the bench moves {} "
                                  "actuators", setup_.actuators, bench_.num_actuators()));
  }
  SetStartPositions(gate_, options_);
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

Server::~Server() = default;

void Server::Serve() {
  bench_.Activate();
  Log(fmt::format("serving {} to OpenFresco clients on {} (n = {})", bench_.Describe(),
                  address(), setup_.dofs()));
  loop_.Serve(stop_);
  HoldBench("server stopping");
  bench_.Deactivate();
  Log("stopped");
}

std::size_t Server::Measure(const Connection& c, std::span<const std::uint8_t> bytes) const {
  if (!c.established) return OpeningSize(bytes);
  return static_cast<std::size_t>(session_->header.data_size) * 8;
}

bool Server::HandleBytes(Connection& c, std::span<const std::uint8_t> bytes) {
  if (c.established) return HandleMessage(c, *session_, DecodeMessage(bytes));
  std::unique_ptr<Session> opened = OpenSession(c, bytes);
  if (opened == nullptr) {
    if (loop_.commander() == 0) HoldBench("session not opened");
    return false;
  }
  if (!loop_.Claim(c.id)) {  // its opening completed while another session is open
    Log(fmt::format("refused a second client from {}: one OpenFresco session at a time",
                    c.peer));
    return false;
  }
  session_ = std::move(opened);
  session_id_ = c.id;
  c.established = true;
  ++sessions_;
  // One session at a time: whoever else is waiting is closed.
  loop_.CloseWaiting(c.id, "one OpenFresco session at a time");
  return true;
}

void Server::Closed(Connection& c, const ServerLoop::Closing& closing) {
  std::string hold;  // why the bench holds; empty: it does not
  switch (closing.cause) {
    case CloseCause::kPeerLeft:
      if (c.established) {
        hold = "client disconnected";
      } else {
        Log(fmt::format("a connection from {} left before its header was complete ({} bytes)",
                        c.peer, c.buffer.size()));
      }
      break;
    case CloseCause::kHandshakeTimeout:
    case CloseCause::kFrameTimeout:
      if (c.established) {
        Log(fmt::format("ERROR: incomplete message: {} bytes (dataSize {} × 8) did not arrive "
                        "within {} s", static_cast<std::size_t>(session_->header.data_size) * 8,
                        session_->header.data_size, options_.heartbeat_timeout));
        hold = "client timed out mid-message";
      } else {
        Log(fmt::format("ERROR: incomplete header from {}: {} bytes of the opening arrived "
                        "within {} s of connecting (handshake timeout); closed",
                        c.peer, c.buffer.size(), options_.handshake_timeout));
      }
      break;
    case CloseCause::kIdleTimeout:
      Log(fmt::format("ERROR: no message for {} s (--heartbeat-timeout)",
                      options_.heartbeat_timeout));
      hold = "client silent beyond the heartbeat timeout";
      break;
    case CloseCause::kGarbled:
    case CloseCause::kTooLong:
      Log(fmt::format("ERROR: {} (from {})", closing.why, c.peer));
      hold = "session not opened";
      break;
    case CloseCause::kMakeRoom:
      Log(fmt::format("closed a connection from {}: {}", c.peer, closing.why));
      break;
    case CloseCause::kByHandler:
      if (!c.established && closing.why == "one OpenFresco session at a time") {
        Log(fmt::format("refused a waiting connection from {}: {}", c.peer, closing.why));
      }
      break;  // the handler logged and held
    case CloseCause::kRefused:
    case CloseCause::kStopping:
      break;
  }
  // A connection that never opened a session never holds the bench another client commands.
  if (!hold.empty() && !closing.another_commands) HoldBench(hold);
  if (c.id == session_id_) {
    session_.reset();
    session_id_ = 0;
  }
}

bool Server::Reply(Connection& c, Session& session, const std::vector<double>& values) {
  return loop_.Send(c, EncodeMessage(values, session.header.data_size));
}

std::unique_ptr<Server::Session> Server::OpenSession(const Connection& c,
                                                    std::span<const std::uint8_t> bytes) {
  Opening opening;
  try {
    opening = DecodeOpening(bytes);
  } catch (const TransferError& e) {
    Log(fmt::format("ERROR: {} (from {})", e.what(), c.peer));
    return nullptr;
  }
  // The token rules of BenchServer (auth.h): constant-time comparison, lockout per address
  // block, a global budget of wrong tokens.
  const auto now = Clock::now();
  if (const auto verdict = auth_.Check(c.peer, now);
      verdict != AuthThrottle::Verdict::kAllowed) {
    Log("ERROR: " + AuthThrottle::RefusalText(verdict, c.peer));
    return nullptr;
  }
  if (!TokensEqual(opening.token, options_.token)) {
    ++auth_failures_;
    if (auth_.RecordFailure(c.peer, now)) {
      Log(fmt::format("auth lockout: {} wrong tokens from block {} (last from {}); its sessions "
                      "are refused for {} s", AuthThrottle::kMaxFailures,
                      AddressBlock(c.peer), c.peer, AuthThrottle::kLockout.count()));
    }
    Log(opening.token.empty()
            ? fmt::format("ERROR: this bench requires a token and the client sent none (from "
                          "{}; the hybridtest token preamble; see docs/openfresco.md)",
                          c.peer)
            : fmt::format("ERROR: wrong token from {}: the client's token does not match the "
                          "bench's (--token-file / HYBRIDTEST_BENCH_TOKEN)", c.peer));
    return nullptr;
  }
  auth_.RecordSuccess(c.peer);
  auto session = std::make_unique<Session>();
  session->header = opening.header;
  try {
    ValidateHeader(session->header);
  } catch (const TransferError& e) {
    Log(fmt::format("ERROR: {}", e.what()));
    return nullptr;
  }
  if (session->header.dofs() != setup_.dofs()) {
    Log(fmt::format("ERROR: the client's element has n = {} degrees of freedom, the setup's "
                    "transform has {} columns (openfresco.transform)",
                    session->header.dofs(), setup_.dofs()));
    return nullptr;
  }
  Log(fmt::format("OpenFresco client connected from {}: n = {}, dataSize = {}", c.peer,
                  setup_.dofs(), session->header.data_size));
  return session;
}

}  // namespace hybridtest::transfer::openfresco
