#pragma once
// MonitorServer: serves one run's monitor over HTTP (monitor/http_server.h, decision 0018) on
// its own threads.
//
//   GET  /                 the page (page_assets.h); /monitor.js, /monitor.css, /uplot.*
//   GET  /api/state        MonitorState::StateJson(): status, t, step, physical_evaluations,
//                          identity, meters, progress and ETA, resumes, actions, ...
//   GET  /api/series?since=SEQ&generation=G   the scopes' history (MonitorState::SeriesJson)
//   POST /api/hold, /api/continue, /api/stop  with `Authorization: Bearer TOKEN`
//
// Who may act (docs/monitor.md, "Threat model"): it binds 127.0.0.1 by default and any other
// address only with a token of at least 16 bytes (transfer/auth.h's CheckBindPolicy). Actions
// need the token even on loopback unless the run was started with `actions_without_token`
// (then any local client may act); with no token and without that flag every action is
// refused (403) and says how to give one. A follower of a journal (`hybridtest monitor`) is
// read-only: actions answer 405.
//
// The operator keeps Stop: the token is compared first, in constant time, and a right token
// is served whatever anyone sent before (no lockout, no global budget). A missing or wrong
// token is answered 401/403 and slows only its own source (source_backoff.h: 429 with
// Retry-After while it waits; only counted failures are logged and listed on the page).
//
// Never in the way of the run: the server reads only the MonitorState, on one thread of its
// own (http_server.h: bounded heads and bodies, a deadline per request and per connection, a
// bounded connection table, the operator's actions handled before the viewers' requests,
// a bounded Stop()). On a real-time run that thread runs SCHED_IDLE and off the stepping
// thread's CPU (background_thread.h).
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "hybridtest/monitor/monitor_state.h"
#include "hybridtest/monitor/operator_control.h"
#include "hybridtest/monitor/http_server.h"
#include "hybridtest/monitor/source_backoff.h"

namespace hybridtest::monitor {

struct MonitorServerOptions {
  std::string host = "127.0.0.1";  // non-loopback needs `token`
  std::uint16_t port = 0;          // 0 picks a free port (see port())
  std::string token;               // the actions' bearer token (may be empty on loopback)
  bool actions_without_token = false;  // an explicit flag of the run: no token for actions
  HttpLimits limits;               // sizes, deadlines and connections (http_server.h)
  bool background = false;         // a real-time run: SCHED_IDLE (background_thread.h)
  int avoid_cpu = -1;              // the stepping thread's CPU, kept free of the server's
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
  void Stop();   // bounded: closes every connection, whatever the clients do

  HttpCounters counters() const { return server_->counters(); }

 private:
  struct Verdict {
    int status = 200;
    std::string why;
    bool log = true;            // false for a source that is waiting (no flood in the log)
    long retry_after = 0;       // [s] for 429
  };
  void Routes();
  Verdict Authorize(const std::string& peer, const std::string& header);

  MonitorState& state_;
  OperatorControl* control_;
  MonitorServerOptions options_;
  std::unique_ptr<HttpServer> server_;
  std::uint16_t port_ = 0;
  std::mutex auth_mutex_;
  SourceBackoff backoff_;
};

}  // namespace hybridtest::monitor
