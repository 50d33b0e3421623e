#pragma once
// Tests that need a peer from a chosen source address: a TCP connection to 127.0.0.1:port
// bound first to `source` (any 127.x.y.z works on Linux), as a guesser rotating its loopback
// source address would make.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdint>
#include <stdexcept>
#include <string>

#include "hybridtest/transfer/socket.h"

namespace hybridtest::transfer::testing {

inline Socket ConnectFrom(const std::string& source, std::uint16_t port) {
  Socket s(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0));
  sockaddr_in from{};
  from.sin_family = AF_INET;
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(port);
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (!s.is_open() || inet_pton(AF_INET, source.c_str(), &from.sin_addr) != 1 ||
      ::bind(s.fd(), reinterpret_cast<sockaddr*>(&from), sizeof from) != 0 ||
      ::connect(s.fd(), reinterpret_cast<sockaddr*>(&to), sizeof to) != 0) {
    throw std::runtime_error("ConnectFrom: cannot connect from " + source);
  }
  return s;
}

}  // namespace hybridtest::transfer::testing
