// See monitor_server.h.
#include "hybridtest/monitor/monitor_server.h"

#include <fmt/core.h>

#include <chrono>

#include "hybridtest/common/error.h"
#include "hybridtest/monitor/background_thread.h"
#include "hybridtest/monitor/page_assets.h"
#include "hybridtest/transfer/auth.h"

namespace hybridtest::monitor {
namespace {

HttpResponse Json(const nlohmann::json& body, int status = 200) {
  HttpResponse res;
  res.status = status;
  res.headers.emplace_back("Cache-Control", "no-store");
  res.content_type = "application/json";
  res.body = JsonText(body);
  return res;
}

// A shared answer (MonitorState::StateBody, SeriesBody): built once, copied to each viewer.
HttpResponse SharedJson(const std::shared_ptr<const std::string>& text) {
  HttpResponse res;
  res.headers.emplace_back("Cache-Control", "no-store");
  res.content_type = "application/json";
  res.body = *text;
  return res;
}

long ParamLong(const HttpRequest& req, const char* name, long fallback) {
  const auto it = req.query.find(name);
  if (it == req.query.end()) return fallback;
  try {
    return std::stol(it->second);
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
    : state_(state), control_(control), options_(std::move(options)) {
  transfer::CheckBindPolicy(options_.host, options_.port, options_.token, "the monitor");
  server_ = std::make_unique<HttpServer>(options_.host, options_.port, options_.limits);
  port_ = server_->port();
  Routes();
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
  const bool background = options_.background;
  const int cpu = options_.avoid_cpu;
  auto log = options_.log;
  server_->Start([background, cpu, log] {
    if (!background) return;
    const std::string note = MoveThisThreadToBackground(cpu);
    if (log) log("server thread: " + note);
  });
}

void MonitorServer::Stop() { server_->Stop(); }

MonitorServer::Verdict MonitorServer::Authorize(const std::string& peer,
                                                const std::string& header) {
  if (options_.token.empty()) {
    if (options_.actions_without_token) return {};
    return {403, "actions need a token: start the run with --token-file FILE (or "
                 "HYBRIDTEST_BENCH_TOKEN), or with --monitor-no-token on a machine you trust"};
  }
  // The token first, in constant time: a right one is served whatever came before.
  if (transfer::TokensEqual(header, "Bearer " + options_.token)) {
    std::lock_guard lock(auth_mutex_);
    backoff_.Success(peer);
    return {};
  }
  // A failed attempt slows its own source only (source_backoff.h).
  std::lock_guard lock(auth_mutex_);
  const auto now = SourceBackoff::Clock::now();
  if (const auto wait = backoff_.Wait(peer, now); wait > SourceBackoff::Clock::duration::zero()) {
    const long s = static_cast<long>(std::chrono::ceil<std::chrono::seconds>(wait).count());
    return {429, fmt::format("too many failed attempts from {}: wait {} s (Retry-After), then "
                             "send the run's token", SourceBackoff::SourceOf(peer), s),
            false, s};
  }
  const auto wait = backoff_.Failure(peer, now);
  const std::string later =
      wait > SourceBackoff::Clock::duration::zero()
          ? fmt::format("; {} waits {} s before its next attempt counts",
                        SourceBackoff::SourceOf(peer),
                        std::chrono::ceil<std::chrono::seconds>(wait).count())
          : "";
  if (header.empty()) {
    return {401, "no token: send `Authorization: Bearer TOKEN` (the run's --token-file)" + later};
  }
  return {403, "wrong token" + later};
}

void MonitorServer::Routes() {
  for (const PageAsset& asset : PageAssets()) {
    server_->Route("GET", std::string(asset.path), [asset](const HttpRequest&) {
      HttpResponse res;
      res.headers.emplace_back("Cache-Control", "no-cache");
      res.content_type = std::string(asset.content_type);
      res.body.assign(asset.body.data(), asset.body.size());
      return res;
    });
  }
  server_->Route("GET", "/api/state", [this](const HttpRequest&) {
    return SharedJson(state_.StateBody());
  });
  server_->Route("GET", "/api/series", [this](const HttpRequest& req) {
    return SharedJson(
        state_.SeriesBody(ParamLong(req, "since", -1), ParamLong(req, "generation", -1)));
  });
  const std::pair<const char*, OperatorAction> actions[] = {
      {"/api/hold", OperatorAction::kHold},
      {"/api/continue", OperatorAction::kContinue},
      {"/api/stop", OperatorAction::kStop}};
  for (const auto& [path, action] : actions) {
    server_->Route("POST", path, [this, action = action](const HttpRequest& req) {
      const std::string origin =
          fmt::format("{} ({})", req.peer, Printable(req.Header("user-agent")));
      auto log = [&](const std::string& line) {
        if (options_.log) options_.log(line);
      };
      if (control_ == nullptr) {
        return Json({{"error", "this monitor follows a journal: it is read-only"}}, 405);
      }
      const Verdict v = Authorize(req.peer, req.Header("authorization"));
      if (v.status != 200) {
        if (v.log) {
          log(fmt::format("{} from {} refused ({}): {}", ActionName(action), origin, v.status,
                          v.why));
          state_.AddAction({{"action", ActionName(action)}, {"origin", origin},
                            {"refused", v.status}, {"why", v.why}});
        }
        HttpResponse res = Json({{"error", v.why}}, v.status);
        if (v.status == 401) res.headers.emplace_back("WWW-Authenticate", "Bearer");
        if (v.status == 429) res.headers.emplace_back("Retry-After", std::to_string(v.retry_after));
        return res;
      }
      const ActionReply reply = control_->Request(action, origin);
      log(fmt::format("{} from {}: {}", ActionName(action), origin, reply.message));
      return Json({{reply.http_status == 200 ? "ok" : "error", reply.message}}, reply.http_status);
    }, /*priority=*/true);
  }
}

}  // namespace hybridtest::monitor
