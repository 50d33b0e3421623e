// See monitor_server.h.
#include "hybridtest/monitor/monitor_server.h"

#include <fmt/core.h>
#include <httplib.h>

#include "hybridtest/common/error.h"
#include "hybridtest/monitor/page_assets.h"

namespace hybridtest::monitor {
namespace {

constexpr std::size_t kMaxBody = 4096;  // [B]

void Json(httplib::Response& res, const nlohmann::json& body, int status = 200) {
  res.status = status;
  res.set_header("Cache-Control", "no-store");
  res.set_content(body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace),
                  "application/json");
}

long ParamLong(const httplib::Request& req, const char* name, long fallback) {
  if (!req.has_param(name)) return fallback;
  try {
    return std::stol(req.get_param_value(name));
  } catch (const std::exception&) {
    return fallback;
  }
}

// Control characters of client-supplied text escaped, and its length bounded, for the logs.
std::string Printable(const std::string& text) {
  std::string out;
  for (char c : text.substr(0, 120)) {
    out += (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) ? '?' : c;
  }
  return out;
}

}  // namespace

MonitorServer::MonitorServer(MonitorState& state, OperatorControl* control,
                             MonitorServerOptions options)
    : state_(state), control_(control), options_(std::move(options)),
      server_(std::make_unique<httplib::Server>()) {
  transfer::CheckBindPolicy(options_.host, options_.port, options_.token, "the monitor");
  const int threads = options_.threads < 2 ? 2 : options_.threads;
  server_->new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
  const auto sec = static_cast<time_t>(options_.io_timeout);
  const auto usec = static_cast<time_t>((options_.io_timeout - static_cast<double>(sec)) * 1e6);
  server_->set_read_timeout(sec, usec);
  server_->set_write_timeout(sec, usec);
  server_->set_keep_alive_timeout(sec > 0 ? sec : 1);
  server_->set_payload_max_length(kMaxBody);
  Routes();
  if (options_.port == 0) {
    const int port = server_->bind_to_any_port(options_.host);
    if (port <= 0) {
      throw TransferError(fmt::format("the monitor cannot listen on {}: no free port", options_.host));
    }
    port_ = static_cast<std::uint16_t>(port);
  } else {
    if (!server_->bind_to_port(options_.host, options_.port)) {
      throw TransferError(fmt::format(
          "the monitor cannot listen on {}:{}: the port is in use or the address is not this "
          "machine's; choose another with --monitor HOST:PORT (port 0 picks a free one)",
          options_.host, options_.port));
    }
    port_ = options_.port;
  }
  state_.SetActionsPolicy(control_ == nullptr              ? "read-only"
                          : options_.actions_without_token ? "open"
                          : options_.token.empty()         ? "refused (no token)"
                                                           : "token");
}

MonitorServer::~MonitorServer() { Stop(); }

std::string MonitorServer::address() const {
  return options_.host.find(':') != std::string::npos
             ? fmt::format("[{}]:{}", options_.host, port_)
             : fmt::format("{}:{}", options_.host, port_);
}

std::string MonitorServer::url() const { return "http://" + address() + "/"; }

void MonitorServer::Start() {
  if (thread_.joinable()) return;
  thread_ = std::thread([this] { server_->listen_after_bind(); });
}

void MonitorServer::Stop() {
  server_->stop();
  if (thread_.joinable()) thread_.join();
}

int MonitorServer::Authorize(const std::string& peer, const std::string& header,
                             std::string& why) {
  if (options_.token.empty()) {
    if (options_.actions_without_token) return 200;
    why = "actions need a token: start the run with --token-file FILE (or "
          "HYBRIDTEST_BENCH_TOKEN), or with --monitor-no-token on a machine you trust";
    return 403;
  }
  std::lock_guard lock(auth_mutex_);
  const auto now = transfer::AuthThrottle::Clock::now();
  const auto verdict = throttle_.Check(peer, now);
  if (verdict != transfer::AuthThrottle::Verdict::kAllowed) {
    why = transfer::AuthThrottle::RefusalText(verdict, peer);
    return 429;
  }
  static constexpr std::string_view kBearer = "Bearer ";
  if (header.empty()) {
    why = "no token: send `Authorization: Bearer TOKEN` (the run's --token-file)";
    return 401;
  }
  if (header.compare(0, kBearer.size(), kBearer) != 0 ||
      !transfer::TokensEqual(std::string_view(header).substr(kBearer.size()), options_.token)) {
    throttle_.RecordFailure(peer, now);
    why = "wrong token";
    return 403;
  }
  throttle_.RecordSuccess(peer);
  return 200;
}

void MonitorServer::Routes() {
  for (const PageAsset& asset : PageAssets()) {
    server_->Get(std::string(asset.path), [asset](const httplib::Request&, httplib::Response& res) {
      res.set_header("Cache-Control", "no-cache");
      res.set_content(asset.body.data(), asset.body.size(), std::string(asset.content_type).c_str());
    });
  }
  server_->Get("/api/state", [this](const httplib::Request&, httplib::Response& res) {
    Json(res, state_.StateJson());
  });
  server_->Get("/api/series", [this](const httplib::Request& req, httplib::Response& res) {
    Json(res, state_.SeriesJson(ParamLong(req, "since", -1), ParamLong(req, "generation", -1)));
  });
  const std::pair<const char*, OperatorAction> actions[] = {
      {"/api/hold", OperatorAction::kHold},
      {"/api/continue", OperatorAction::kContinue},
      {"/api/stop", OperatorAction::kStop}};
  for (const auto& [path, action] : actions) {
    server_->Post(path, [this, action = action](const httplib::Request& req,
                                                httplib::Response& res) {
      const std::string origin =
          fmt::format("{} ({})", req.remote_addr, Printable(req.get_header_value("User-Agent")));
      auto log = [&](const std::string& line) {
        if (options_.log) options_.log(line);
      };
      if (control_ == nullptr) {
        Json(res, {{"error", "this monitor follows a journal: it is read-only"}}, 405);
        return;
      }
      std::string why;
      const int status = Authorize(req.remote_addr, req.get_header_value("Authorization"), why);
      if (status != 200) {
        if (status == 401) res.set_header("WWW-Authenticate", "Bearer");
        log(fmt::format("{} from {} refused ({}): {}", ActionName(action), origin, status, why));
        state_.AddAction({{"action", ActionName(action)}, {"origin", origin},
                          {"refused", status}, {"why", why}});
        Json(res, {{"error", why}}, status);
        return;
      }
      const ActionReply reply = control_->Request(action, origin);
      log(fmt::format("{} from {}: {}", ActionName(action), origin, reply.message));
      Json(res, {{reply.http_status == 200 ? "ok" : "error", reply.message}}, reply.http_status);
    });
  }
}

}  // namespace hybridtest::monitor
