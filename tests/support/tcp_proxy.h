#pragma once
// A delay-and-loss TCP proxy for tests of networked transfer systems (docs/multi-site.md):
// listens on 127.0.0.1 (port 0), forwards every connection to 127.0.0.1:`upstream`, delays
// every chunk by `delay` [s] one way, counts the bytes, and can drop the link: Drop() closes
// every forwarded connection and refuses new ones until Restore(). Bounded: at most
// kMaxPairs connections at once, every wait bounded by a 5 ms poll; Stop() (or the destructor)
// joins every thread.
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace hybridtest::test_support {

class TcpProxy {
 public:
  static constexpr int kMaxPairs = 8;
  TcpProxy(std::uint16_t upstream, double delay);
  ~TcpProxy();
  TcpProxy(const TcpProxy&) = delete;
  TcpProxy& operator=(const TcpProxy&) = delete;

  std::uint16_t port() const { return port_; }
  void Drop();     // the link goes down: open connections closed, new ones refused
  void Restore();  // the link comes back
  void Stop();
  std::uint64_t bytes_up() const { return up_.load(); }      // client → server [bytes]
  std::uint64_t bytes_down() const { return down_.load(); }  // server → client [bytes]

 private:
  struct Pair;
  void AcceptLoop();
  void Pump(std::shared_ptr<Pair> pair);

  std::uint16_t upstream_;
  double delay_;
  int listener_ = -1;
  std::uint16_t port_ = 0;
  std::atomic<bool> stop_{false}, dropped_{false};
  std::atomic<std::uint64_t> up_{0}, down_{0};
  std::mutex mutex_;
  std::vector<std::shared_ptr<Pair>> pairs_;
  std::vector<std::thread> threads_;
  std::thread acceptor_;
};

}  // namespace hybridtest::test_support
