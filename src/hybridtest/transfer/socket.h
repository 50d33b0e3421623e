#pragma once
// Thin POSIX TCP helpers for the bench protocol: an owning socket handle, a listener, a
// connect with a timeout, and frame I/O in which every read is bounded by poll(). No call in
// this file blocks without a bound, except Listener::Accept's caller-chosen poll interval.
#include <cstdint>
#include <string>

#include "hybridtest/transfer/frame.h"

namespace hybridtest::transfer {

// An owned file descriptor; closes on destruction. Move-only.
class Socket {
 public:
  Socket() = default;
  explicit Socket(int fd) : fd_(fd) {}
  Socket(Socket&& other) noexcept : fd_(other.fd_) { other.fd_ = -1; }
  Socket& operator=(Socket&& other) noexcept;
  Socket(const Socket&) = delete;
  Socket& operator=(const Socket&) = delete;
  ~Socket() { Close(); }

  int fd() const { return fd_; }
  bool is_open() const { return fd_ >= 0; }
  void Close() noexcept;

 private:
  int fd_ = -1;
};

// "HOST:PORT" split and checked. IPv6 literals go in brackets: "[::1]:7471". Port 0 is allowed
// (pick a free port). Throws ConfigError naming `where` and the text given.
struct HostPort {
  std::string host;
  std::uint16_t port = 0;
};
HostPort ParseHostPort(const std::string& text, const std::string& where);

// True if `host` resolves only to loopback addresses (127.0.0.0/8 or ::1).
// Throws ConfigError if it does not resolve.
bool IsLoopbackHost(const std::string& host);

// Opens a TCP connection with TCP_NODELAY set, giving up after `timeout` [s].
// Throws TransferError naming host:port and the reason.
Socket ConnectTcp(const std::string& host, std::uint16_t port, double timeout);

// A listening TCP socket (SO_REUSEADDR, backlog 4).
class Listener {
 public:
  // Binds and listens. Throws TransferError if the address is in use or cannot be bound.
  Listener(const std::string& host, std::uint16_t port);
  std::uint16_t port() const { return port_; }  // the bound port (resolved when 0 was asked)
  const std::string& host() const { return host_; }
  std::string address() const;  // "HOST:PORT", an IPv6 host in brackets ("[::1]:7471")
  int fd() const { return socket_.fd(); }

  // Waits up to `timeout` [s] for a connection. Returns a closed Socket on timeout.
  // The accepted socket has TCP_NODELAY set.
  Socket Accept(double timeout);

 private:
  Socket socket_;
  std::string host_;
  std::uint16_t port_ = 0;
};

// The numeric address of the peer of a connected socket ("127.0.0.1", "::1"); "unknown" if it
// cannot be read.
std::string PeerAddress(int fd);

enum class ReadStatus { kFrame, kTimeout, kClosed };

// Writes all bytes, waiting up to `timeout` [s] in total. Returns false if the peer closed the
// connection or the time ran out (no SIGPIPE is raised).
bool SendAll(int fd, const std::vector<std::uint8_t>& bytes, double timeout);

// Reads exactly out.size() bytes, waiting up to `timeout` [s] in total. Returns kFrame when
// all arrived, kTimeout or kClosed (EOF, reset, or EOF part-way) otherwise. For fixed-length
// protocols without frames (e.g. OpenFresco's, transfer/openfresco/wire.h).
ReadStatus ReadBytes(int fd, double timeout, std::vector<std::uint8_t>& out);

// Reads one frame, waiting up to `timeout` [s] in total for all of its bytes. Returns kTimeout
// or kClosed (orderly shutdown, reset, or EOF mid-frame) without throwing; throws
// TransferError when the bytes received are not a valid frame (see DecodeFrame).
ReadStatus ReadFrame(int fd, double timeout, Frame& out);

}  // namespace hybridtest::transfer
