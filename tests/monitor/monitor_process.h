#pragma once
// Support for the monitor's end-to-end tests: `hybridtest run ... --monitor 127.0.0.1:0` in a
// child process, the port it announces, and its API through an HTTP client. Every wait is
// bounded.
#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "integration/child_process.h"
#include "integration/resume_support.h"

namespace hybridtest::testing {

// A run with a live monitor; its stdout and stderr go to `log`.
class MonitoredRun {
 public:
  MonitoredRun(std::vector<std::string> args, const fs::path& log)
      : child_(HybridtestArgv(args), log) {
    // "hybridtest: monitor at http://127.0.0.1:PORT/" on stderr, within 30 s.
    const std::regex announcement(R"(monitor at http://127\.0\.0\.1:(\d+)/)");
    for (int i = 0; i < 3000 && port_ == 0; ++i) {
      std::smatch m;
      const std::string out = child_.output();
      if (std::regex_search(out, m, announcement)) port_ = std::stoi(m[1].str());
      if (port_ == 0) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    if (port_ != 0) client_ = std::make_unique<httplib::Client>("127.0.0.1", port_);
    if (client_) client_->set_read_timeout(10);
  }
  int port() const { return port_; }
  Child& child() { return child_; }

  // GET /api/state (null if no answer).
  nlohmann::json State() {
    if (!client_) return nullptr;
    auto res = client_->Get("/api/state");
    return res && res->status == 200 ? nlohmann::json::parse(res->body) : nlohmann::json();
  }
  // POST /api/<action> with `token` (none if empty): the HTTP status, -1 if no answer.
  int Post(const std::string& action, const std::string& token = "") {
    if (!client_) return -1;
    httplib::Headers headers;
    if (!token.empty()) headers.emplace("Authorization", "Bearer " + token);
    auto res = client_->Post(("/api/" + action).c_str(), headers, "", "text/plain");
    return res ? res->status : -1;
  }
  // Polls the state until `pred` holds (≤ 60 s).
  template <typename Pred>
  bool WaitState(Pred&& pred) {
    for (int i = 0; i < 1200; ++i) {
      const nlohmann::json s = State();
      if (!s.is_null() && pred(s)) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return false;
  }

 private:
  Child child_;
  int port_ = 0;
  std::unique_ptr<httplib::Client> client_;
};

// The journal's lines with the lab-time columns taken out (they count the hold's time).
inline std::vector<std::string> WithoutLabTime(const std::vector<std::string>& lines) {
  if (lines.empty()) return lines;
  const std::vector<std::string> header = SplitCsv(lines[0]);
  std::vector<std::string> out;
  for (const std::string& line : lines) {
    const std::vector<std::string> fields = SplitCsv(line);
    std::string kept;
    for (std::size_t i = 0; i < fields.size() && i < header.size(); ++i) {
      if (header[i].size() >= 9 && header[i].ends_with("_lab_time")) continue;
      kept += fields[i] + ",";
    }
    out.push_back(kept);
  }
  return out;
}

}  // namespace hybridtest::testing
