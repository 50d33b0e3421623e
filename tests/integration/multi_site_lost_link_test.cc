// A multi-site run whose link stays down longer than the configured wait (issue 49, contract;
// docs/multi-site.md "Lost links"), end to end with the commands: three `hybridtest site`
// processes behind the test's delay-and-loss proxies, `hybridtest run` of
// examples/10_multi_site/multi-site.yaml. Site r3's link drops for good in the middle of the
// run: the run stops with exit 4 and every committed row on disk (a prefix of the
// uninterrupted run's journal); the link comes back, `hybridtest resume` finishes, and the
// journal equals the uninterrupted run's (lab times aside: the resume's re-imposition moves
// count on the benches' clocks). About 5 s: three runs of 300 steps and six site processes.
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "integration/resume_support.h"
#include "support/listening_process.h"
#include "support/tcp_proxy.h"

namespace hybridtest::testing {
namespace {

const std::string kSites = kSource + "/examples/10_multi_site/";

std::string Replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// `hybridtest site` for blade `b` (1..3), its config and journal in `dir`.
test_support::ListeningProcess StartSite(const fs::path& dir, int b) {
  const std::string name = "site-r" + std::to_string(b) + ".yaml";
  const std::string text = Replaced(test_support::ReadText(kSites + name),
                                    "../rotor/bench-ideal.yaml",
                                    kSource + "/examples/rotor/bench-ideal.yaml");
  test_support::WriteText(dir / name, text);
  return test_support::ListeningProcess(
      {HYBRIDTEST_BINARY, "site", "--config", (dir / name).string(), "--listen", "127.0.0.1:0"},
      test_support::CurrentEnvironment(), "listening on 127\\.0\\.0\\.1:([0-9]+) \\(",
      "hybridtest site");
}

// The example's run config, 0.3 s long, its sites at `ports`, waiting `wait` [s] for a link.
fs::path RunConfig(const fs::path& dir, const std::vector<std::uint16_t>& ports, double wait) {
  std::string text = Replaced(test_support::ReadText(kSites + "multi-site.yaml"),
                              "duration: 1.0", "duration: 0.3");
  for (int b = 1; b <= 3; ++b) {
    text = Replaced(text, "address: 127.0.0.1:748" + std::to_string(b),
                    "address: 127.0.0.1:" +
                        std::to_string(ports[static_cast<std::size_t>(b - 1)]));
    text = Replaced(text, "reconnect_wait: 10 ", "reconnect_wait: " + std::to_string(wait) + " ");
    text = Replaced(text, "propose_timeout: 5 ", "propose_timeout: 1 ");
    text = Replaced(text, "execute_timeout: 30 ", "execute_timeout: 1 ");
  }
  const fs::path config = dir / "multi-site.yaml";
  test_support::WriteText(config, text);
  return config;
}

// Three `hybridtest site` processes (their files in `dir`), each behind a proxy.
struct ProxiedSites {
  explicit ProxiedSites(const fs::path& dir) {
    for (int b = 1; b <= 3; ++b) {
      sites.push_back(StartSite(dir, b));
      proxies.push_back(std::make_unique<test_support::TcpProxy>(sites.back().port(), 0.0));
      ports.push_back(proxies.back()->port());
    }
  }
  ~ProxiedSites() {
    proxies.clear();
    for (auto& s : sites) s.Terminate(10.0);
  }
  std::vector<test_support::ListeningProcess> sites;
  std::vector<std::unique_ptr<test_support::TcpProxy>> proxies;
  std::vector<std::uint16_t> ports;
};

TEST(MultiSiteCommands, ALinkLostBeyondTheWaitStopsWithExit4AndResumeFinishesTheSameJournal) {
  const fs::path dir = ResumeTestDir("multi-site-lost");
  // The uninterrupted run, on sites of its own (a run leaves the blades away from p0).
  const fs::path reference = dir / "reference.csv";
  {
    fs::create_directories(dir / "reference");
    ProxiedSites sites(dir / "reference");
    const fs::path config = RunConfig(dir / "reference", sites.ports, 0.5);
    ASSERT_EQ(RunToEnd(RunArgs(config.string(), reference), dir / "reference.log"), 0);
  }
  const auto expected = ReadLines(reference);
  ASSERT_GT(expected.size(), 300u);
  // The same run on fresh sites; r3's link drops for good once a third of the journal is on
  // disk (a bounded wait, ended by the run's own end too).
  ProxiedSites sites(dir);
  auto& proxies = sites.proxies;
  const fs::path config = RunConfig(dir, sites.ports, 0.5);
  const fs::path csv = dir / "lost.csv";
  {
    Child child(HybridtestArgv(RunArgs(config.string(), csv)), dir / "lost.log");
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    for (;;) {
      std::error_code error;
      const auto size = fs::file_size(csv, error);
      if (!error && size >= fs::file_size(reference) / 3) break;
      if (std::chrono::steady_clock::now() > deadline || child.WaitExit(0.0) != -2) break;
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    proxies[2]->Drop();
    const int status = child.WaitExit(60.0);
    ASSERT_EQ(status, 4) << child.output();
    EXPECT_NE(child.output().find("substructures.r3"), std::string::npos) << child.output();
    EXPECT_NE(child.output().find("reconnect_wait"), std::string::npos) << child.output();
  }
  // Every committed row is on disk: the stopped journal is a prefix of the uninterrupted one.
  const auto stopped = ReadLines(csv);
  ASSERT_GT(stopped.size(), 2u);
  ASSERT_LT(stopped.size(), expected.size());
  ExpectSameJournal(std::vector<std::string>(expected.begin(),
                                             expected.begin() +
                                                 static_cast<std::ptrdiff_t>(stopped.size())),
                    stopped, true);
  // The link is back: resume finishes with the uninterrupted run's journal.
  proxies[2]->Restore();
  const auto [status, output] = Resume(csv, {"--quiet"}, dir / "resume.log");
  ASSERT_EQ(status, 0) << output;
  ExpectSameJournal(expected, ReadLines(csv), true);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hybridtest::testing
