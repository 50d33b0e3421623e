#pragma once
// Viewers of the live monitor for its end-to-end tests, on threads of the test process; every
// loop ends when Join() is called (or the object goes).
#include <httplib.h>
#include <poll.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "monitor/raw_http.h"

namespace hybridtest::testing {

// Viewers on their own threads until `done`: pollers ask for the state and the series as the
// page does (keep-alive, every 0.5 s); drippers send a request line, then one header line
// every 2 s, and connect again when cut off. `nice`: the pollers' own niceness (19: they
// stand for browsers on other machines, their client work kept off this machine's cores).
class Viewers {
 public:
  Viewers(int port, int pollers, int drippers, int nice = 0) {
    for (int i = 0; i < pollers; ++i) {
      threads_.emplace_back([this, port, i, nice] {
        if (nice != 0) ::setpriority(PRIO_PROCESS, static_cast<id_t>(::syscall(SYS_gettid)), nice);
        httplib::Client client("127.0.0.1", port);
        client.set_connection_timeout(5);
        client.set_read_timeout(5);
        for (long n = 0; !done_.load(); ++n) {
          auto res = client.Get(n % 2 == 0 ? "/api/state" : "/api/series?since=-1");
          if (res && res->status == 200) ++answered_;
          Sleep(0.5 + 0.01 * i);
        }
      });
    }
    for (int i = 0; i < drippers; ++i) {
      threads_.emplace_back([this, port] {
        while (!done_.load()) {
          const int fd = ConnectFrom("127.0.0.1", port);
          if (fd < 0) {
            Sleep(0.2);
            continue;
          }
          bool open = SendAll(fd, "GET /api/state HTTP/1.1\r\n");
          for (int line = 0; open && !done_.load() && line < 1000; ++line) {
            Sleep(2.0);
            open = !done_.load() && SendAll(fd, "X-Drip-" + std::to_string(line) + ": 1\r\n");
            pollfd p{fd, POLLIN, 0};
            if (open && ::poll(&p, 1, 0) > 0) open = false;  // answered (408) or closed
          }
          ::close(fd);
          ++drips_cut_;
        }
      });
    }
  }
  ~Viewers() { Join(); }
  void Join() {
    done_ = true;
    for (auto& t : threads_) {
      if (t.joinable()) t.join();
    }
  }
  long answered() const { return answered_.load(); }
  long drips_cut() const { return drips_cut_.load(); }

 private:
  void Sleep(double s) const {
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(s);
    while (!done_.load() && std::chrono::steady_clock::now() < until) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
  std::atomic<bool> done_{false};
  std::atomic<long> answered_{0};
  std::atomic<long> drips_cut_{0};
  std::vector<std::thread> threads_;
};

}  // namespace hybridtest::testing
