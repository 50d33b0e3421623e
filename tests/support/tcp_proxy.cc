// See tcp_proxy.h.
#include "support/tcp_proxy.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <deque>
#include <stdexcept>

namespace hybridtest::test_support {
namespace {

using ProxyClock = std::chrono::steady_clock;

int ConnectLoopback(std::uint16_t port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
    ::close(fd);
    return -1;
  }
  const int one = 1;
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  return fd;
}

struct Chunk {
  ProxyClock::time_point due;
  std::vector<char> bytes;
};

}  // namespace

struct TcpProxy::Pair {
  int client = -1, server = -1;
  std::atomic<bool> closed{false};
};

TcpProxy::TcpProxy(std::uint16_t upstream, double delay) : upstream_(upstream), delay_(delay) {
  listener_ = ::socket(AF_INET, SOCK_STREAM, 0);
  const int one = 1;
  ::setsockopt(listener_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t size = sizeof a;
  if (::bind(listener_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 ||
      ::listen(listener_, 8) != 0 ||
      ::getsockname(listener_, reinterpret_cast<sockaddr*>(&a), &size) != 0) {
    ::close(listener_);
    throw std::runtime_error("TcpProxy: cannot listen on 127.0.0.1");
  }
  port_ = ntohs(a.sin_port);
  acceptor_ = std::thread([this] { AcceptLoop(); });
}

TcpProxy::~TcpProxy() { Stop(); }

void TcpProxy::Stop() {
  if (stop_.exchange(true)) return;
  if (acceptor_.joinable()) acceptor_.join();
  for (auto& t : threads_) t.join();
  threads_.clear();
  for (auto& p : pairs_) {
    ::close(p->client);
    ::close(p->server);
  }
  pairs_.clear();
  ::close(listener_);
}

void TcpProxy::Drop() {
  dropped_ = true;
  std::lock_guard lock(mutex_);
  for (auto& p : pairs_) {
    p->closed = true;
    ::shutdown(p->client, SHUT_RDWR);
    ::shutdown(p->server, SHUT_RDWR);
  }
}

void TcpProxy::Restore() { dropped_ = false; }

void TcpProxy::AcceptLoop() {
  while (!stop_) {
    pollfd p{listener_, POLLIN, 0};
    if (::poll(&p, 1, 5) <= 0) continue;
    const int client = ::accept(listener_, nullptr, nullptr);
    if (client < 0) continue;
    std::lock_guard lock(mutex_);
    if (dropped_ || static_cast<int>(threads_.size()) >= kMaxPairs * 4) {
      ::close(client);  // the link is down (or the proxy is full): nothing gets through
      continue;
    }
    const int server = ConnectLoopback(upstream_);
    if (server < 0) {
      ::close(client);
      continue;
    }
    const int one = 1;
    ::setsockopt(client, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    auto pair = std::make_shared<Pair>();
    pair->client = client;
    pair->server = server;
    pairs_.push_back(pair);
    threads_.emplace_back([this, pair] { Pump(pair); });
  }
}

// Both directions of one pair in one thread: read what arrives, write what is due.
void TcpProxy::Pump(std::shared_ptr<Pair> pair) {
  std::deque<Chunk> to_server, to_client;
  const auto delay = std::chrono::duration_cast<ProxyClock::duration>(
      std::chrono::duration<double>(delay_));
  std::vector<char> buffer(65536);
  const auto flush = [&](std::deque<Chunk>& queue, int fd, std::atomic<std::uint64_t>& count) {
    const auto now = ProxyClock::now();
    while (!queue.empty() && queue.front().due <= now) {
      const auto& b = queue.front().bytes;
      std::size_t done = 0;
      while (done < b.size()) {
        const ssize_t n = ::send(fd, b.data() + done, b.size() - done, MSG_NOSIGNAL);
        if (n <= 0) return false;
        done += static_cast<std::size_t>(n);
      }
      count += b.size();
      queue.pop_front();
    }
    return true;
  };
  while (!stop_ && !pair->closed) {
    pollfd p[2] = {{pair->client, POLLIN, 0}, {pair->server, POLLIN, 0}};
    ::poll(p, 2, 1);
    bool open = true;
    for (int k = 0; k < 2 && open; ++k) {
      if ((p[k].revents & (POLLIN | POLLHUP | POLLERR)) == 0) continue;
      const ssize_t n = ::recv(p[k].fd, buffer.data(), buffer.size(), 0);
      if (n <= 0) {
        open = false;
        break;
      }
      (k == 0 ? to_server : to_client)
          .push_back({ProxyClock::now() + delay, {buffer.begin(), buffer.begin() + n}});
    }
    if (!open || !flush(to_server, pair->server, up_) || !flush(to_client, pair->client, down_)) {
      break;
    }
  }
  pair->closed = true;
  ::shutdown(pair->client, SHUT_RDWR);
  ::shutdown(pair->server, SHUT_RDWR);
}

}  // namespace hybridtest::test_support
