// See client.h.
#include "hybridtest/transfer/openfresco/client.h"

#include <fmt/core.h>

#include "hybridtest/common/error.h"

namespace hybridtest::transfer::openfresco {

Client::Client(ClientOptions options) : options_(std::move(options)), header_(PlainHeader(1)) {
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
  return fmt::format("OpenFresco site server at {}:{} (n = 1, {} and {})", options_.host,
                     options_.port, options_.units.length_name, options_.units.force_name);
}

void Client::Fail(const std::string& message) {
  socket_.Close();
  throw TransferError(fmt::format("OpenFresco site server at {}:{}: {}", options_.host,
                                  options_.port, message));
}

void Client::Activate() {
  if (socket_.is_open()) return;
  socket_ = ConnectTcp(options_.host, options_.port, options_.connect_timeout);
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
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(header_.data_size) * 8);
  const ReadStatus status = ReadBytes(socket_.fd(), options_.reply_timeout, bytes);
  if (status == ReadStatus::kTimeout) {
    Fail(fmt::format("no complete reply to {} within {} s", what, options_.reply_timeout));
  }
  if (status == ReadStatus::kClosed) {
    Fail(fmt::format("the connection closed while waiting for the reply to {} (the server "
                     "refused the last command or left; see its log)", what));
  }
  return DecodeMessage(bytes);
}

Measurement Client::Execute(double command) {
  const long n = ++commands_;
  Send({static_cast<double>(Action::kSetTrialResponse), command, 0.0, 0.0},
       fmt::format("the trial response of command {}", n));
  Measurement m;
  m.position = Request(Action::kGetDisp, fmt::format("getDisp of command {}", n))[0];
  m.force = Request(Action::kGetForce, fmt::format("getForce of command {}", n))[0];
  m.lab_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - activated_).count();
  return m;
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
