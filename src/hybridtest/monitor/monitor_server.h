#pragma once
// MonitorServer: serves one run's monitor over HTTP (cpp-httplib) on its own threads.
//
//   GET  /                 the page (page_assets.h); /monitor.js, /monitor.css, /uplot.*
//   GET  /api/state        MonitorState::StateJson(): status, t, step, physical_evaluations,
//                          identity, meters, progress and ETA, resumes, actions, ...
//   GET  /api/series?since=SEQ&generation=G   the scopes' history (MonitorState::SeriesJson)
//   POST /api/hold, /api/continue, /api/stop  with `Authorization: Bearer TOKEN`
//
// The rules of the bench server (transfer/auth.h): it binds 127.0.0.1 by default and any other
// address only with a token of at least 16 bytes. Actions need the token even on loopback
// (401 without an Authorization header, 403 with a wrong token; both throttled per address
// block and globally, 429 while locked out) unless the run was started with
// `actions_without_token` (then any local client may act); with no token and without that
// flag every action is refused (403) and says how to give one. A follower of a journal
// (`hybridtest monitor`) is read-only: actions answer 405.
//
// Never in the way of the run: the server reads only the MonitorState. Requests are small
// (bodies over 4 KiB are refused), a connection idle or stalled for `io_timeout` is dropped,
// and a fixed pool of threads serves every viewer.
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "hybridtest/monitor/monitor_state.h"
#include "hybridtest/monitor/operator_control.h"
#include "hybridtest/transfer/auth.h"

namespace httplib {
class Server;
}

namespace hybridtest::monitor {

struct MonitorServerOptions {
  std::string host = "127.0.0.1";  // non-loopback needs `token`
  std::uint16_t port = 0;          // 0 picks a free port (see port())
  std::string token;               // the actions' bearer token (may be empty on loopback)
  bool actions_without_token = false;  // an explicit flag of the run: no token for actions
  int threads = 8;                 // the pool that serves every viewer
  double io_timeout = 5.0;         // a connection silent this long is closed. Unit: [s]
  std::function<void(const std::string&)> log;  // one line per action or refusal; may be empty
};

class MonitorServer {
 public:
  // Binds at once (port() is known). `control` is null for a read-only follower. Throws
  // ConfigError for a non-loopback host without a long token, TransferError if the address
  // cannot be bound.
  MonitorServer(MonitorState& state, OperatorControl* control, MonitorServerOptions options);
  ~MonitorServer();  // stops
  MonitorServer(const MonitorServer&) = delete;
  MonitorServer& operator=(const MonitorServer&) = delete;

  std::uint16_t port() const { return port_; }
  std::string address() const;  // "HOST:PORT"
  std::string url() const;      // "http://HOST:PORT/"

  void Start();  // serves on a thread of its own
  void Stop();

 private:
  void Routes();
  int Authorize(const std::string& peer, const std::string& header, std::string& why);

  MonitorState& state_;
  OperatorControl* control_;
  MonitorServerOptions options_;
  std::unique_ptr<httplib::Server> server_;
  std::uint16_t port_ = 0;
  std::mutex auth_mutex_;
  transfer::AuthThrottle throttle_;
  std::thread thread_;
};

}  // namespace hybridtest::monitor
