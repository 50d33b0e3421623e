#pragma once
// Three in-process sites of examples/10_multi_site/ for the multi-site tests: each site's
// config read as `hybridtest site` reads it, served on 127.0.0.1 (port 0) in a thread, its
// journal in a scratch directory; a run's substructures pointed at them.
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/io/site_config.h"
#include "hybridtest/runner/session.h"
#include "hybridtest/transfer/site/site_client.h"
#include "hybridtest/transfer/site/site_server.h"
#include "support/tcp_proxy.h"
#include "support/temp_dir.h"
#include "transfer/serving_thread.h"

namespace hybridtest::runner::testing_site {

inline const std::string kExample =
    std::string(HYBRIDTEST_SOURCE_DIR) + "/examples/10_multi_site/";

// The run's duration [s] and its step count (dt = 1 ms in every config here).
inline void SetDuration(io::RunSpec& spec, double duration) {
  spec.scheme.duration = duration;
  spec.scheme.steps = io::StepCount(duration, 0.001);
}

// Site `s`'s config (0..2), with its emulated bench starting at `initial_mm` [mm] if given
// (a copy of the example's site and bench files in `dir`).
inline io::SiteConfig SiteConfigOf(const std::filesystem::path& dir, int s,
                                   std::optional<double> initial_mm) {
  const std::string site = "site-r" + std::to_string(s + 1) + ".yaml";
  if (!initial_mm) return io::LoadSiteConfig(kExample + site);
  const std::string bench = "bench-r" + std::to_string(s + 1) + ".yaml";
  test_support::WriteText(dir / bench,
                          test_support::ReadText(kExample + "../rotor/bench-ideal.yaml") +
                              "\n  initial_position_mm: " + std::to_string(*initial_mm) + "\n");
  std::string text = test_support::ReadText(kExample + site);
  const std::string from = "../rotor/bench-ideal.yaml";
  text.replace(text.find(from), from.size(), bench);
  test_support::WriteText(dir / site, text);
  return io::LoadSiteConfig((dir / site).string());
}

class Sites {
 public:
  // stroke_max: a site index (0..2) and the stroke_max [m] it refuses beyond; initial_mm: a
  // site index and where its bench's actuator starts [mm] (default: the bench's p0, 20 mm).
  Sites(const std::filesystem::path& dir, const std::map<int, double>& stroke_max,
        const std::map<int, double>& initial_mm = {}) {
    for (int s = 0; s < 3; ++s) {
      const auto initial = initial_mm.find(s);
      io::SiteConfig c = SiteConfigOf(
          dir, s, initial == initial_mm.end() ? std::nullopt : std::optional(initial->second));
      c.server.port = 0;
      c.server.journal = (dir / ("site-r" + std::to_string(s + 1) + ".journal")).string();
      journals_.push_back(c.server.journal);
      c.server.journal_max_bytes = std::uintmax_t{16} << 20;  // the start's disk check: 80 MiB free
      if (const auto it = stroke_max.find(s); it != stroke_max.end()) {
        c.server.limits[0].stroke_max = it->second;
      }
      benches_.push_back(c.transfer.make());
      servers_.push_back(std::make_unique<transfer::site::SiteServer>(*benches_.back(), c.server));
      threads_.push_back(
          std::make_unique<transfer::testing::ServingThread<transfer::site::SiteServer>>(
              *servers_.back()));
    }
  }
  ~Sites() {
    threads_.clear();  // stop and join before the servers go
  }
  // Points the run's substructures r1..r3 at the sites (through `proxy_ports` if given).
  // Only the first `count` of them (the others keep their config's transfer).
  void Point(io::RunSpec& spec, std::vector<std::uint16_t> proxy_ports = {},
             double reconnect_wait = 10.0, int count = 3) {
    for (int s = 0; s < count; ++s) {
      transfer::site::SiteClientOptions o;
      o.name = "substructures.r" + std::to_string(s + 1);
      o.port = proxy_ports.empty() ? servers_[static_cast<std::size_t>(s)]->port()
                                   : proxy_ports[static_cast<std::size_t>(s)];
      o.reconnect_wait = reconnect_wait;
      o.propose_timeout = 1.0;
      o.execute_timeout = 1.0;
      spec.substructures.at(static_cast<std::size_t>(s)).physical->transfer = {
          "site", [o] { return std::make_unique<transfer::site::SiteClient>(o); }};
    }
  }
  transfer::site::SiteServer& server(int s) { return *servers_[static_cast<std::size_t>(s)]; }
  std::string journal(int s) const {
    return test_support::ReadText(journals_[static_cast<std::size_t>(s)]);
  }

 private:
  std::vector<std::string> journals_;
  std::vector<std::unique_ptr<transfer::TransferSystem>> benches_;
  std::vector<std::unique_ptr<transfer::site::SiteServer>> servers_;
  std::vector<std::unique_ptr<transfer::testing::ServingThread<transfer::site::SiteServer>>>
      threads_;
};

// One delay-and-loss proxy in front of each site (support/tcp_proxy.h).
struct Proxies {
  Proxies(Sites& sites, double delay) {
    for (int s = 0; s < 3; ++s) {
      at.push_back(std::make_unique<test_support::TcpProxy>(sites.server(s).port(), delay));
      ports.push_back(at.back()->port());
    }
  }
  std::vector<std::unique_ptr<test_support::TcpProxy>> at;
  std::vector<std::uint16_t> ports;
};

// Every committed row of the journal, as the journal holds it.
class RowRecorder final : public SessionObserver {
 public:
  void OnCommit(const CommitEvent& e) override {
    if (e.kind == RowKind::kCommitted) rows.emplace_back(e.row.begin(), e.row.end());
  }
  std::vector<std::vector<double>> rows;
};

struct RunRows {
  SessionStatus status = SessionStatus::kWorking;
  std::string reason;
  std::vector<std::vector<double>> rows;
};

inline RunRows Run(io::RunSpec spec) {
  spec.output.files = false;
  spec.quiet = true;
  Session session(std::move(spec));
  RowRecorder recorder;
  session.AddObserver(recorder);
  const StepResult r = session.Run();
  return {r.status, r.reason, std::move(recorder.rows)};
}

// (step, stage) of the first refused proposal in a site journal.
inline std::optional<std::pair<long, int>> RefusedStepStage(const std::string& journal) {
  std::istringstream lines(journal);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.rfind("propose ", 0) != 0 || line.find(" refuse:") == std::string::npos) continue;
    std::istringstream words(line);
    std::string kind, run;
    long seq = 0, step = 0;
    int stage = 0;
    words >> kind >> run >> seq >> step >> stage;
    return std::make_pair(step, stage);
  }
  return std::nullopt;
}

// True if the journal executed a transaction at (step, stage).
inline bool ExecutedAt(const std::string& journal, std::pair<long, int> at) {
  std::istringstream lines(journal);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.rfind("execute ", 0) != 0) continue;
    std::istringstream words(line);
    std::string kind, run;
    long seq = 0, step = 0;
    int stage = 0;
    words >> kind >> run >> seq >> step >> stage;
    if (step == at.first && stage == at.second) return true;
  }
  return false;
}

// Every key (run, seq) executed more than once in a journal.
inline int RepeatedExecutes(const std::string& journal) {
  std::istringstream lines(journal);
  std::string line;
  std::map<std::pair<std::string, long>, int> seen;
  int repeated = 0;
  while (std::getline(lines, line)) {
    if (line.rfind("execute ", 0) != 0) continue;
    std::istringstream words(line);
    std::string kind, run;
    long seq = 0;
    words >> kind >> run >> seq;
    if (++seen[{run, seq}] == 2) ++repeated;
  }
  return repeated;
}

}  // namespace hybridtest::runner::testing_site
