#pragma once
// Raw HTTP/1.1 over loopback for the monitor's tests, where an HTTP library would hide what is
// tested: a client that binds a chosen source address (127.0.0.2, 127.0.0.3, ... are all this
// machine's), a viewer that drips its head one line at a time, a flood of header lines. Every
// wait is bounded by poll().
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <string>

namespace hybridtest::testing {

// A TCP connection to 127.0.0.1:`port` from `source` (port 0), or -1.
inline int ConnectFrom(const std::string& source, int port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return -1;
  sockaddr_in local{};
  local.sin_family = AF_INET;
  ::inet_pton(AF_INET, source.c_str(), &local.sin_addr);
  sockaddr_in remote{};
  remote.sin_family = AF_INET;
  remote.sin_port = htons(static_cast<std::uint16_t>(port));
  ::inet_pton(AF_INET, "127.0.0.1", &remote.sin_addr);
  if (::bind(fd, reinterpret_cast<sockaddr*>(&local), sizeof local) != 0 ||
      ::connect(fd, reinterpret_cast<sockaddr*>(&remote), sizeof remote) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

inline bool SendAll(int fd, const std::string& bytes) {
  std::size_t sent = 0;
  while (sent < bytes.size()) {
    const ssize_t n = ::send(fd, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
    if (n <= 0) return false;
    sent += static_cast<std::size_t>(n);
  }
  return true;
}

// What the server sent until it closed, or until `timeout` seconds passed.
inline std::string ReadUntilClosed(int fd, double timeout) {
  std::string out;
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout);
  char chunk[4096];
  while (std::chrono::steady_clock::now() < until) {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, 50) <= 0) continue;
    const ssize_t n = ::recv(fd, chunk, sizeof chunk, 0);
    if (n <= 0) break;
    out.append(chunk, static_cast<std::size_t>(n));
  }
  return out;
}

// The status of an answer ("HTTP/1.1 200 OK" → 200), -1 if none.
inline int StatusOf(const std::string& answer) {
  if (answer.rfind("HTTP/1.", 0) != 0 || answer.size() < 12) return -1;
  return std::atoi(answer.substr(9, 3).c_str());
}

// One request from `source` (Connection: close): the answer's status, -1 if none in `timeout`.
inline int RequestFrom(const std::string& source, int port, const std::string& method,
                       const std::string& path, const std::string& token = "",
                       double timeout = 5.0) {
  const int fd = ConnectFrom(source, port);
  if (fd < 0) return -1;
  std::string req = method + " " + path + " HTTP/1.1\r\nHost: 127.0.0.1\r\n";
  if (!token.empty()) req += "Authorization: Bearer " + token + "\r\n";
  req += "Content-Length: 0\r\nConnection: close\r\n\r\n";
  const int status = SendAll(fd, req) ? StatusOf(ReadUntilClosed(fd, timeout)) : -1;
  ::close(fd);
  return status;
}

}  // namespace hybridtest::testing
