#pragma once
// A raw OpenFresco peer for tests: a plain TCP socket that sends hand-packed int32 and float64
// words (memcpy of native little-endian values, not our encoder) and reads replies, every
// wait bounded by poll.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <vector>

namespace hybridtest::testing {

class RawPeer {
 public:
  explicit RawPeer(std::uint16_t port) {
    fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(port);
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (fd_ < 0 || ::connect(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
      if (fd_ >= 0) ::close(fd_);
      throw std::runtime_error("RawPeer: cannot connect to 127.0.0.1");
    }
  }
  ~RawPeer() { Close(); }
  RawPeer(const RawPeer&) = delete;
  RawPeer& operator=(const RawPeer&) = delete;

  void Close() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }

  bool SendBytes(const std::vector<std::uint8_t>& bytes) {
    std::size_t sent = 0;
    while (sent < bytes.size()) {
      const ssize_t w = ::send(fd_, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
      if (w <= 0) return false;
      sent += static_cast<std::size_t>(w);
    }
    return true;
  }
  bool SendInts(const std::vector<std::int32_t>& words) {
    std::vector<std::uint8_t> bytes(words.size() * 4);
    for (std::size_t i = 0; i < words.size(); ++i) std::memcpy(&bytes[4 * i], &words[i], 4);
    return SendBytes(bytes);
  }
  // `words` zero-padded to `data_size` float64 words.
  bool SendDoubles(const std::vector<double>& words, int data_size) {
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(data_size) * 8, 0);
    for (std::size_t i = 0; i < words.size(); ++i) std::memcpy(&bytes[8 * i], &words[i], 8);
    return SendBytes(bytes);
  }

  // Reads `count` float64 words within `timeout` [s]; nullopt on timeout or EOF.
  std::optional<std::vector<double>> ReadDoubles(std::size_t count, double timeout = 5.0) {
    std::vector<std::uint8_t> bytes(count * 8);
    if (!ReadExactly(bytes, timeout)) return std::nullopt;
    std::vector<double> out(count);
    for (std::size_t i = 0; i < count; ++i) std::memcpy(&out[i], &bytes[8 * i], 8);
    return out;
  }

  // True if the server closes the connection within `timeout` [s] (EOF or reset).
  bool ClosedByPeer(double timeout = 5.0) {
    pollfd pfd{fd_, POLLIN, 0};
    if (::poll(&pfd, 1, static_cast<int>(timeout * 1e3)) <= 0) return false;
    char c = 0;
    return ::recv(fd_, &c, 1, 0) <= 0;
  }

 private:
  bool ReadExactly(std::vector<std::uint8_t>& out, double timeout) {
    std::size_t got = 0;
    while (got < out.size()) {
      pollfd pfd{fd_, POLLIN, 0};
      if (::poll(&pfd, 1, static_cast<int>(timeout * 1e3)) <= 0) return false;
      const ssize_t r = ::recv(fd_, out.data() + got, out.size() - got, 0);
      if (r <= 0) return false;
      got += static_cast<std::size_t>(r);
    }
    return true;
  }
  int fd_ = -1;
};

}  // namespace hybridtest::testing
