#pragma once
// AdsLink: one AMS/TCP connection from hybridtest to an ADS server (a TwinCAT PLC runtime, or
// `hybridtest bench --protocol ads`), straight to its port 48898 without a local AMS router.
// Requests are sent one at a time and matched to their answer by invoke id; every wait is
// bounded (connect, send and answer). A timeout, a closed connection or a garbled answer
// closes the link (its state is unknown) and throws TransferError; an ADS error code in an
// answer throws AdsError and leaves the link open, so that a hold can still be written.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/ads/ads_codec.h"
#include "hybridtest/transfer/socket.h"

namespace hybridtest::transfer::ads {

// An ADS error code in an answer (0x700 and up: the device; below: AMS and router).
class AdsError : public TransferError {
 public:
  AdsError(const std::string& message, std::uint32_t code) : TransferError(message), code_(code) {}
  std::uint32_t code() const { return code_; }

 private:
  std::uint32_t code_;
};

struct AdsEndpoint {
  std::string host = "127.0.0.1";
  std::uint16_t tcp_port = kAdsTcpPort;
  AmsAddress target{{{127, 0, 0, 1, 1, 1}}, kPlcPort};
  // This computer's AmsNetId, as the PLC's route names it; unset: the IP address of the
  // connection's local end followed by ".1.1" (TwinCAT's usual choice).
  std::optional<AmsNetId> local_net_id;
  std::uint16_t local_port = 32905;  // the AMS port hybridtest's requests come from
};

// The IPv4 address of a connection's local end (peer: its remote end) as the AmsNetId
// "a.b.c.d.1.1", TwinCAT's usual name for a computer; 127.0.0.1.1.1 for an IPv6 connection.
AmsNetId EndpointNetId(int fd, bool peer);

// Reads one AMS/TCP message (prefix and what follows) within `timeout` [s]. Returns kTimeout
// or kClosed without throwing; throws TransferError for a prefix announcing too much.
ReadStatus ReadAmsMessage(int fd, double timeout, Prefix& prefix, std::vector<std::uint8_t>& body);

class AdsLink {
 public:
  explicit AdsLink(AdsEndpoint endpoint) : endpoint_(std::move(endpoint)) {}

  // Opens the TCP connection (bounded by `timeout` [s]). Throws TransferError.
  void Connect(double timeout);
  void Close() noexcept { socket_.Close(); }
  bool is_open() const { return socket_.is_open(); }

  // "HOST:PORT (AmsNetId N, AMS port 851)" and "the ADS server at " that, for messages.
  std::string Where() const;
  std::string Describe() const { return "the ADS server at " + Where(); }
  const AdsEndpoint& endpoint() const { return endpoint_; }
  AmsNetId local_net_id() const { return source_.net_id; }
  long requests() const { return requests_; }

  // One request (`what` names it in messages) and its answer's payload, within `timeout` [s].
  std::vector<std::uint8_t> Request(Command command, std::span<const std::uint8_t> payload,
                                    double timeout, const std::string& what);

  // The commands, each throwing AdsError for a non-zero result.
  std::vector<std::uint8_t> ReadWrite(std::uint32_t group, std::uint32_t offset,
                                      std::uint32_t read_length,
                                      std::span<const std::uint8_t> data, double timeout,
                                      const std::string& what);
  void Write(std::uint32_t group, std::uint32_t offset, std::span<const std::uint8_t> data,
             double timeout, const std::string& what);
  StateResponse ReadState(double timeout);
  DeviceInfo ReadDeviceInfo(double timeout);
  // A sum read: one answer per item (its result not checked: the caller names the symbol).
  std::vector<DataResponse> SumRead(std::span<const SubRequest> items, double timeout,
                                    const std::string& what);
  std::vector<std::uint32_t> SumWrite(std::span<const SubRequest> items, double timeout,
                                      const std::string& what);

 private:
  [[noreturn]] void Fail(const std::string& message);
  void CheckResult(std::uint32_t result, const std::string& what) const;
  // A ReadWrite of the payload `request` (already encoded): its checked read data.
  std::vector<std::uint8_t> ReadWrite(std::span<const std::uint8_t> request, double timeout,
                                      const std::string& what);
  // decode(), a garbled answer (TransferError) closing the link; an AdsError passes.
  template <class Decode>
  auto Decoded(Decode decode, const std::string& what) -> decltype(decode());

  AdsEndpoint endpoint_;
  AmsAddress source_;
  Socket socket_;
  std::uint32_t invoke_id_ = 0;
  long requests_ = 0;
  bool answered_ = false;  // the server has answered a request on this connection
};

}  // namespace hybridtest::transfer::ads
