// The monitor's page in a real browser (headless Chromium, Debian's `chromium`; skipped with a
// message where it is absent), on the paper's emulated run (examples/rotor/emulated.yaml, 2 s
// of it on a bench paced in real time, so that it lasts long enough on any machine):
// loaded twice 2 s apart during the run, the page's text shows two different simulated
// times, the physical slot's force and its limit; a Hold without the token is refused and the
// page lists the refusal; after the run, the page shows "finished".
#include <fmt/core.h>

#include <cmath>
#include <cstdlib>
#include <regex>
#include <utility>
#include <vector>

#include "monitor/example_config.h"
#include "monitor/monitor_process.h"
#include "support/listening_process.h"
#include "monitor/chromium.h"
#include "support/run_command.h"

namespace hybridtest::testing {
namespace {

// The page's DOM once its scripts have run (their first polls answered).
std::string DumpDom(const std::string& chromium, int port, const fs::path& profile) {
  const auto [status, dom] = RunCommand(
      chromium + " --headless --no-sandbox --disable-gpu --no-first-run --user-data-dir=" +
          profile.string() + " --virtual-time-budget=3000 --dump-dom http://127.0.0.1:" +
          std::to_string(port) + "/",
      90, false);
  EXPECT_EQ(status, 0) << dom;
  return dom;
}

std::string Capture(const std::string& text, const std::string& pattern) {
  std::smatch m;
  return std::regex_search(text, m, std::regex(pattern)) ? m[1].str() : "";
}

TEST(MonitorBrowser, ThePageFollowsTheRunAndShowsItsEnd) {
  const std::string chromium = FindChromium();
  if (chromium.empty()) {
    GTEST_SKIP() << "chromium not found: the monitor's browser test needs Debian's `chromium` "
                    "(scripts/install-deps.sh)";
  }
  const fs::path dir = ResumeTestDir("monitor_browser");
  const fs::path csv = dir / "emulated.csv";
  test_support::WriteText(dir / "token", "browser-test-token-0123456789\n");
  // The paper's emulated run, 2 s of it, on a bench paced in real time with a few ms per
  // command: the run lasts tens of seconds on any disk, long enough to load the page twice.
  std::string bench = test_support::ReadText(kSource + "/examples/rotor/bench-cantilever.yaml");
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{
           {"pacing: accelerated", "pacing: realtime"},
           {R"(lag: \{[^}]*\})", "lag: {type: none}"},
           {"delay_ms: 2 ", "delay_ms: 0 "},
           {"dwell_ms: 100", "dwell_ms: 1"},
           {"window_ms: 500", "window_ms: 1"},
           {R"(overhead_ms: \d+)", "overhead_ms: 2"}}) {
    const std::string edited = std::regex_replace(bench, std::regex(from), to);
    ASSERT_NE(edited, bench) << "bench-cantilever.yaml no longer has " << from;
    bench = edited;
  }
  test_support::WriteText(dir / "bench-cantilever.yaml", bench);
  std::string config = test_support::ReadText(kSource + "/examples/rotor/emulated.yaml");
  config = std::regex_replace(config, std::regex("duration: 10.0"), "duration: 2.0");
  test_support::WriteText(dir / "emulated.yaml", config);
  MonitoredRun run({"run", (dir / "emulated.yaml").string(), "--out", csv.string(),
                    "--quiet", "--monitor", "127.0.0.1:0", "--token-file",
                    (dir / "token").string(), "--monitor-linger", "120"},
                   dir / "run.log");
  ASSERT_NE(run.port(), 0) << run.child().output();
  ASSERT_TRUE(run.WaitState([](const auto& s) { return s["step"].template get<long>() > 0; }));

  // Twice, 2 s apart, during the run: two different simulated times.
  const std::string first = DumpDom(chromium, run.port(), dir / "profile1");
  std::this_thread::sleep_for(std::chrono::seconds(2));
  const std::string second = DumpDom(chromium, run.port(), dir / "profile2");
  const std::string t1 = Capture(first, R"(id="t">([0-9.]+)<)");
  const std::string t2 = Capture(second, R"(id="t">([0-9.]+)<)");
  ASSERT_FALSE(t1.empty()) << first;
  ASSERT_FALSE(t2.empty()) << second;
  EXPECT_NE(t1, t2);
  // The physical slot's force and its limit (force_hard = 300 N in emulated.yaml).
  EXPECT_FALSE(Capture(first, R"(Actuator r1 force (-?[0-9.e+-]+) N)").empty()) << first;
  EXPECT_EQ(Capture(first, R"(limit \(force_hard\) ([0-9.e+]+) N)"), "300.0") << first;

  // A Hold without the token is refused, and the page says so.
  EXPECT_EQ(run.Post("hold"), 401);
  EXPECT_NE(run.State()["status"], "holding");

  // After the run: "finished", the refusal listed.
  ASSERT_TRUE(run.WaitState([](const auto& s) { return s["status"] == "finished"; }));
  const std::string last = DumpDom(chromium, run.port(), dir / "profile3");
  EXPECT_EQ(Capture(last, R"(id="status" class="badge finished">([a-z]+)<)"), "finished") << last;
  EXPECT_NE(last.find("hold refused (401)"), std::string::npos) << last;
  EXPECT_EQ(Capture(last, R"(id="t">([0-9.]+)<)"), "2.0000");
  run.child().Signal(SIGINT);  // ends the linger
  EXPECT_EQ(run.child().WaitExit(30.0), 0) << run.child().output();
  fs::remove_all(dir);
}

// Issue 38's contract: the two-actuator blade (examples/06_blade_two_actuators/bouc-wen.yaml,
// 1 s of it): the live page names both actuators with their positions and forces, and the
// loop's x axis (displacement from each actuator's own p0) starts near 0, not at p0; the
// follower's page of the finished run shows both actuators' limits and the lab time its
// sidecar records.
TEST(MonitorBrowser, BothActuatorsOfTheBladeLiveAndFollowed) {
  const std::string chromium = FindChromium();
  if (chromium.empty()) GTEST_SKIP() << "chromium not found (scripts/install-deps.sh)";
  const fs::path dir = ResumeTestDir("monitor_browser_blade");
  const fs::path config =
      WriteExampleConfig(dir, "06_blade_two_actuators", "bouc-wen.yaml",
                         {{"duration: 10.0", "duration: 1.0"}},
                         {"blade_tip.yaml", "bench-2act-bouc-wen.yaml"});
  const fs::path csv = dir / "blade.csv";
  {
    MonitoredRun run({"run", config.string(), "--out", csv.string(), "--quiet",
                      "--monitor", "127.0.0.1:0", "--monitor-no-token", "--monitor-linger", "120"},
                     dir / "run.log");
    ASSERT_NE(run.port(), 0) << run.child().output();
    ASSERT_TRUE(run.WaitState([](const auto& s) { return s["step"].template get<long>() > 100; }));
    const std::string page = DumpDom(chromium, run.port(), dir / "profile1");
    for (const char* name : {"blade1_a1", "blade1_a2"}) {
      EXPECT_FALSE(Capture(page, std::string("Actuator ") + name + R"( force (-?[0-9.e+-]+) N)").empty())
          << name << "\n" << page;
      EXPECT_NE(page.find(std::string("position ") + name), std::string::npos) << name;
    }
    // The loop's x range: displacements from p0 (0.02 and 0.03 m) of a few mm, around 0.
    const std::string range = Capture(page, R"re(id="scope-loop"[^>]*><canvas[^>]*data-x-range="([^"]+)")re");
    ASSERT_FALSE(range.empty()) << page;
    const double x0 = std::stod(range.substr(0, range.find(' ')));
    EXPECT_LT(std::abs(x0), 0.01) << range;
    ASSERT_TRUE(run.WaitState([](const auto& s) { return s["status"] == "finished"; }));
    run.child().Signal(SIGINT);
    EXPECT_EQ(run.child().WaitExit(30.0), 0) << run.child().output();
  }
  test_support::ListeningProcess follower(
      {HYBRIDTEST_BINARY, "monitor", csv.string(), "--listen", "127.0.0.1:0"},
      test_support::CurrentEnvironment(), R"(at http://127\.0\.0\.1:(\d+)/)",
      "hybridtest monitor");
  const std::string page = DumpDom(chromium, follower.port(), dir / "profile2");
  for (const char* name : {"blade1_a1", "blade1_a2"}) {
    EXPECT_EQ(Capture(page, std::string("Actuator ") + name + R"( force -?[0-9.e+-]+ N; limit \(force_hard\) ([0-9.e+]+) N)"),
              "3000") << name << "\n" << page;
  }
  const double lab = Sidecar(csv)["statistics"]["lab_time_s"].get<double>();
  EXPECT_EQ(Capture(page, R"(id="lab-time">([^<]+)<)"), fmt::format("{:.1f} s", lab)) << page;
  EXPECT_NE(page.find("a run that has ended, from its files (read-only)"), std::string::npos);
  follower.Terminate(5.0);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hybridtest::testing
