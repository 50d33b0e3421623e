// See ads_link.h.
#include "hybridtest/transfer/ads/ads_link.h"

#include <arpa/inet.h>
#include <fmt/core.h>
#include <netinet/in.h>
#include <sys/socket.h>

namespace hybridtest::transfer::ads {
AmsNetId EndpointNetId(int fd, bool peer) {
  sockaddr_storage address{};
  socklen_t size = sizeof(address);
  auto* any = reinterpret_cast<sockaddr*>(&address);
  AmsNetId id{{127, 0, 0, 1, 1, 1}};
  if ((peer ? ::getpeername(fd, any, &size) : ::getsockname(fd, any, &size)) == 0 &&
      address.ss_family == AF_INET) {
    const std::uint32_t ip = ntohl(reinterpret_cast<const sockaddr_in*>(&address)->sin_addr.s_addr);
    for (std::size_t i = 0; i < 4; ++i) id.bytes[i] = static_cast<std::uint8_t>(ip >> (24 - 8 * i));
  }
  return id;
}

ReadStatus ReadAmsMessage(int fd, double timeout, Prefix& prefix, std::vector<std::uint8_t>& body) {
  std::vector<std::uint8_t> head(kPrefixSize);
  const ReadStatus status = ReadBytes(fd, timeout, head);
  if (status != ReadStatus::kFrame) return status;
  prefix = DecodePrefix(head);
  body.resize(prefix.length);
  return body.empty() ? ReadStatus::kFrame : ReadBytes(fd, timeout, body);
}

void AdsLink::Connect(double timeout) {
  try {
    socket_ = ConnectTcp(endpoint_.host, endpoint_.tcp_port, timeout);
  } catch (const TransferError& e) {
    throw TransferError(fmt::format(
        "{} (ADS, Beckhoff's AMS/TCP): is the PLC's TwinCAT router running and reachable on TCP "
        "port {} there (docs/ads.md, \"Routes and AmsNetIds\")?", e.what(), endpoint_.tcp_port));
  }
  source_ = {endpoint_.local_net_id.value_or(EndpointNetId(socket_.fd(), false)), endpoint_.local_port};
  answered_ = false;
}

std::string AdsLink::Where() const {
  return fmt::format("{}:{} (AmsNetId {}, AMS port {})", endpoint_.host,
                     endpoint_.tcp_port, FormatAmsNetId(endpoint_.target.net_id),
                     endpoint_.target.port);
}

void AdsLink::Fail(const std::string& message) {
  Close();
  throw TransferError(message);
}

std::vector<std::uint8_t> AdsLink::Request(Command command, std::span<const std::uint8_t> payload,
                                           double timeout, const std::string& what) {
  if (!is_open()) {
    throw TransferError(fmt::format("{}: not connected (the connection was lost or closed) "
                                    "for {}", Describe(), what));
  }
  AmsPacket request;
  request.header.target = endpoint_.target;
  request.header.source = source_;
  request.header.command = command;
  request.header.state_flags = kFlagRequest;
  request.header.invoke_id = ++invoke_id_;
  request.data.assign(payload.begin(), payload.end());
  ++requests_;
  if (!SendAll(socket_.fd(), EncodePacket(request), timeout)) {
    Fail(fmt::format("{}: the request for {} could not be sent within {} s (connection lost)",
                     Describe(), what, timeout));
  }
  Prefix prefix;
  std::vector<std::uint8_t> body;
  ReadStatus status;
  try {
    status = ReadAmsMessage(socket_.fd(), timeout, prefix, body);
  } catch (const TransferError& e) {
    Fail(fmt::format("{}: garbled answer to {}: {}", Describe(), what, e.what()));
  }
  if (status == ReadStatus::kTimeout) {
    Fail(fmt::format("{} did not answer {} within {} s; the connection was closed",
                     Describe(), what, timeout));
  }
  if (status == ReadStatus::kClosed) {
    const std::string hint =
        answered_ ? "the connection was lost"
                  : fmt::format("a TwinCAT PLC closes the connection of a client it has no route "
                                "for: add a route for AmsNetId {} (this computer) on the PLC, or "
                                "set transfer.local_ams_net_id to the AmsNetId of an existing "
                                "route (docs/ads.md, \"Routes\")", FormatAmsNetId(source_.net_id));
    Fail(fmt::format("{} closed the connection instead of answering {}: {}", Describe(), what,
                     hint));
  }
  AmsPacket answer;
  try {
    if (prefix.reserved != kTcpAmsCommand) {
      throw TransferError(fmt::format("a router message 0x{:04X} instead of an AMS packet",
                                      prefix.reserved));
    }
    answer = DecodePacket(body);
  } catch (const TransferError& e) {
    Fail(fmt::format("{}: garbled answer to {}: {}", Describe(), what, e.what()));
  }
  if (answer.header.invoke_id != request.header.invoke_id ||
      answer.header.command != command || answer.header.state_flags != kFlagResponse) {
    Fail(fmt::format("{}: the answer to {} is not the answer to this request (invoke id {}, "
                     "command {}, flags 0x{:04X}; sent invoke id {}, command {})", Describe(),
                     what, answer.header.invoke_id, static_cast<int>(answer.header.command),
                     answer.header.state_flags, request.header.invoke_id,
                     static_cast<int>(command)));
  }
  answered_ = true;
  if (answer.header.error != 0) {
    throw AdsError(fmt::format("{} refused {}: ADS error {}", Describe(), what,
                               AdsErrorName(answer.header.error)), answer.header.error);
  }
  return std::move(answer.data);
}

void AdsLink::CheckResult(std::uint32_t result, const std::string& what) const {
  if (result != 0) {
    throw AdsError(fmt::format("{} refused {}: ADS error {}", Describe(), what,
                               AdsErrorName(result)), result);
  }
}

template <class Decode>
auto AdsLink::Decoded(Decode decode, const std::string& what) -> decltype(decode()) {
  try {
    return decode();
  } catch (const AdsError&) {
    throw;
  } catch (const TransferError& e) {
    Fail(fmt::format("{}: garbled answer to {}: {}", Describe(), what, e.what()));
  }
}

std::vector<std::uint8_t> AdsLink::ReadWrite(std::uint32_t group, std::uint32_t offset,
                                             std::uint32_t read_length,
                                             std::span<const std::uint8_t> data, double timeout,
                                             const std::string& what) {
  return ReadWrite(ReadWriteRequest(group, offset, read_length, data), timeout, what);
}

std::vector<std::uint8_t> AdsLink::ReadWrite(std::span<const std::uint8_t> request, double timeout,
                                             const std::string& what) {
  const std::vector<std::uint8_t> payload = Request(Command::kReadWrite, request, timeout, what);
  DataResponse r = Decoded([&] { return DecodeDataResponse(payload); }, what);
  CheckResult(r.result, what);
  return std::move(r.data);
}

void AdsLink::Write(std::uint32_t group, std::uint32_t offset, std::span<const std::uint8_t> data,
                    double timeout, const std::string& what) {
  const std::vector<std::uint8_t> payload =
      Request(Command::kWrite, WriteRequest(group, offset, data), timeout, what);
  CheckResult(Decoded([&] { return DecodeResultResponse(payload); }, what), what);
}

StateResponse AdsLink::ReadState(double timeout) {
  const std::vector<std::uint8_t> payload = Request(Command::kReadState, {}, timeout, "ReadState");
  const StateResponse r = Decoded([&] { return DecodeStateResponse(payload); }, "ReadState");
  CheckResult(r.result, "ReadState");
  return r;
}

DeviceInfo AdsLink::ReadDeviceInfo(double timeout) {
  const std::vector<std::uint8_t> payload =
      Request(Command::kReadDeviceInfo, {}, timeout, "ReadDeviceInfo");
  DeviceInfo r = Decoded([&] { return DecodeDeviceInfo(payload); }, "ReadDeviceInfo");
  CheckResult(r.result, "ReadDeviceInfo");
  return r;
}

std::vector<DataResponse> AdsLink::SumRead(std::span<const SubRequest> items, double timeout,
                                           const std::string& what) {
  std::vector<std::uint32_t> lengths;
  for (const SubRequest& s : items) lengths.push_back(s.length);
  const std::vector<std::uint8_t> data = ReadWrite(SumReadRequest(items), timeout, what);
  return Decoded([&] { return DecodeSumReadAnswer(data, lengths); }, what);
}

std::vector<std::uint32_t> AdsLink::SumWrite(std::span<const SubRequest> items, double timeout,
                                             const std::string& what) {
  const std::vector<std::uint8_t> data = ReadWrite(SumWriteRequest(items), timeout, what);
  return Decoded([&] { return DecodeSumWriteAnswer(data, items.size()); }, what);
}

}  // namespace hybridtest::transfer::ads
