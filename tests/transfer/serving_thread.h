#pragma once
// A server (BenchServer, openfresco::Server: anything with Serve() and Stop()) serving in a
// background thread for tests: Serve() starts on construction; the destructor calls Stop()
// and joins. An exception out of Serve() is caught and remembered (failed()).
#include <atomic>
#include <thread>

namespace hybridtest::transfer::testing {

template <typename Server>
class ServingThread {
 public:
  explicit ServingThread(Server& server)
      : server_(server), thread_([this] {
          try {
            server_.Serve();
          } catch (...) {
            failed_ = true;
          }
        }) {}
  ~ServingThread() {
    server_.Stop();
    thread_.join();
  }
  ServingThread(const ServingThread&) = delete;
  ServingThread& operator=(const ServingThread&) = delete;

  bool failed() const { return failed_.load(); }

 private:
  Server& server_;
  std::atomic<bool> failed_{false};
  std::thread thread_;
};

}  // namespace hybridtest::transfer::testing
