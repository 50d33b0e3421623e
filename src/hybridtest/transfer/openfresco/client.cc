// See client.h.
#include "hybridtest/transfer/openfresco/client.h"

#include <fmt/core.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>

#include <cerrno>

#include "hybridtest/common/error.h"

namespace hybridtest::transfer::openfresco {

Client::Client(ClientOptions options) : options_(std::move(options)) {
  if (options_.dofs < 1 || options_.dofs > kMaxDofs) {
    throw ConfigError(fmt::format("OpenFresco client: dofs = {}: expected the element's degrees "
                                  "of freedom, 1 to {}", options_.dofs, kMaxDofs));
  }
  header_ = PlainHeader(options_.dofs);
  trial_.assign(1 + 3 * static_cast<std::size_t>(options_.dofs), 0.0);
  trial_[0] = static_cast<double>(Action::kSetTrialResponse);
  if (!(options_.connect_timeout > 0.0) || !(options_.reply_timeout > 0.0)) {
    throw ConfigError(fmt::format("OpenFresco client: connect_timeout = {} s, reply_timeout = "
                                  "{} s: expected positive times",
                                  options_.connect_timeout, options_.reply_timeout));
  }
}

Client::~Client() {
  try {
    Deactivate();
  } catch (...) {
    // A destructor must not throw; the server holds when it sees the disconnect.
  }
}

std::string Client::Describe() const {
  return fmt::format("OpenFresco site server at {}:{} (n = {}, {} and {})", options_.host,
                     options_.port, options_.dofs, options_.units.length_name,
                     options_.units.force_name);
}

void Client::Fail(const std::string& message) {
  socket_.Close();
  throw TransferError(fmt::format("OpenFresco site server at {}:{}: {}", options_.host,
                                  options_.port, message));
}

void Client::Activate() {
  if (socket_.is_open()) return;
  try {
    socket_ = ConnectTcp(options_.host, options_.port, options_.connect_timeout);
  } catch (const TransferError& e) {
    throw TransferError(fmt::format("{} (OpenFresco generic TCP protocol); is the OpenFresco "
                                    "experimental site or `hybridtest bench --protocol "
                                    "openfresco` running there?", e.what()));
  }
  std::vector<std::uint8_t> opening;
  if (!options_.token.empty()) opening = EncodeTokenPreamble(options_.token);
  const std::vector<std::uint8_t> header = EncodeHeader(header_);
  opening.insert(opening.end(), header.begin(), header.end());
  if (!SendAll(socket_.fd(), opening, options_.reply_timeout)) {
    Fail("the header could not be sent (connection closed or stalled)");
  }
  activated_ = std::chrono::steady_clock::now();
}

void Client::Send(const std::vector<double>& values, const std::string& what) {
  if (!socket_.is_open()) {
    Fail(fmt::format("not connected while sending {}; call Activate()", what));
  }
  if (!SendAll(socket_.fd(), EncodeMessage(values, header_.data_size), options_.reply_timeout)) {
    Fail(fmt::format("could not send {} (connection closed or stalled)", what));
  }
}

std::vector<double> Client::Request(Action action, const std::string& what) {
  Send({static_cast<double>(action)}, what);
  return ReadReply(what);
}

std::vector<double> Client::ReadReply(const std::string& what) {
  const std::size_t expected = static_cast<std::size_t>(header_.data_size) * 8;
  std::vector<std::uint8_t> bytes(expected);
  std::size_t got = 0;
  const auto deadline = std::chrono::steady_clock::now() +
                        std::chrono::duration<double>(options_.reply_timeout);
  const auto lengths = [&] {
    return fmt::format("{} bytes of the reply to {} arrived; a reply is exactly dataSize = {} "
                       "float64 values ({} bytes) for n = {}", got, what, header_.data_size,
                       expected, options_.dofs);
  };
  while (got < expected) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    pollfd p{socket_.fd(), POLLIN, 0};
    const int ready = left.count() > 0 ? poll(&p, 1, static_cast<int>(left.count())) : 0;
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0) {
      if (got == 0) {
        Fail(fmt::format("no reply to {} within {} s", what, options_.reply_timeout));
      }
      Fail(fmt::format("a reply of the wrong length: within {} s only {} (the server's dataSize "
                       "or n differs from this element's)", options_.reply_timeout, lengths()));
    }
    const ssize_t r = recv(socket_.fd(), bytes.data() + got, expected - got, 0);
    if (r < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (r <= 0) {
      if (got == 0) {
        Fail(fmt::format("the connection closed while waiting for the reply to {} (the server "
                         "refused the last command or left; see its log)", what));
      }
      Fail(fmt::format("a reply of the wrong length: the connection closed after {}", lengths()));
    }
    got += static_cast<std::size_t>(r);
  }
  CheckNothingPending(what);
  return DecodeMessage(bytes);
}

void Client::CheckNothingPending(const std::string& after) {
  int pending = 0;
  if (ioctl(socket_.fd(), FIONREAD, &pending) == 0 && pending > 0) {
    Fail(fmt::format("a reply of the wrong length: {} bytes more than the {} of dataSize = {} "
                     "float64 values arrived with the reply to {} (the server's dataSize or n "
                     "differs from this element's: n = {})", pending,
                     static_cast<std::size_t>(header_.data_size) * 8, header_.data_size, after,
                     options_.dofs));
  }
}

void Client::Execute(std::span<const double> commands, std::span<Measurement> out) {
  const auto n = static_cast<std::size_t>(options_.dofs);
  if (commands.size() != n || out.size() != n) {
    throw TransferError(fmt::format("OpenFresco site server at {}:{}: {} commands and {} "
                                    "measurements for an element of dofs = {}", options_.host,
                                    options_.port, commands.size(), out.size(), n));
  }
  const long count = ++commands_;
  // Bytes left over from the last reply (a late tail of a reply longer than dataSize).
  if (socket_.is_open() && count > 1) {
    CheckNothingPending(fmt::format("getForce of command {}", count - 1));
  }
  std::copy(commands.begin(), commands.end(), trial_.begin() + 1);
  Send(trial_, fmt::format("the trial response of command {}", count));
  const std::vector<double> disp =
      Request(Action::kGetDisp, fmt::format("getDisp of command {}", count));
  const std::vector<double> force =
      Request(Action::kGetForce, fmt::format("getForce of command {}", count));
  const double lab_time =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - activated_).count();
  for (std::size_t k = 0; k < n; ++k) out[k] = {disp[k], force[k], lab_time};
}

void Client::Deactivate() {
  if (!socket_.is_open()) return;
  const bool sent = SendAll(socket_.fd(),
                            EncodeMessage(std::vector<double>{static_cast<double>(Action::kDie)},
                                          header_.data_size),
                            options_.reply_timeout);
  socket_.Close();
  if (!sent) {
    throw TransferError(fmt::format("OpenFresco site server at {}:{}: could not send DIE (99); "
                                    "the connection was already closed", options_.host,
                                    options_.port));
  }
}

}  // namespace hybridtest::transfer::openfresco
