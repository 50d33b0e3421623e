// The monitor's layout at 1400 × 1000 (issue 50: the scopes were below the fold): the page's
// own files (src/hybridtest/monitor/web) in headless Chromium at that window size, with a probe
// script appended that records where the meters and the scopes are. Both must start and the
// scopes end within the first screen (the window's inner height). Skipped with a message where
// Debian's `chromium` is absent. A stand-in for the server's /api/series gives the scopes two
// slots and two actuators to draw; the meters panel holds its "no physical actuator" line.
// Checked by hand: main's layout puts the scopes' bottom at 1016 px of 857, this one at 647.
#include <gtest/gtest.h>

#include <regex>
#include <string>

#include "monitor/chromium.h"
#include "support/run_command.h"
#include "support/temp_dir.h"

namespace hybridtest::testing {
namespace {

const std::string kWeb = std::string(HYBRIDTEST_SOURCE_DIR) + "/src/hybridtest/monitor/web";

double Attribute(const std::string& dom, const std::string& name) {
  std::smatch m;
  if (!std::regex_search(dom, m, std::regex(name + "=\"(-?[0-9.]+)\""))) return -1.0;
  return std::stod(m[1].str());
}

TEST(MonitorLayout, MetersAndScopesAreOnTheFirstScreenAt1400x1000) {
  const std::string chromium = FindChromium();
  if (chromium.empty()) GTEST_SKIP() << "chromium not found (scripts/install-deps.sh)";
  const auto dir = test_support::FreshTempDir("monitor_layout");
  // The page's own HTML, CSS and script from files, with a stand-in for the server's series
  // (two slots, two actuators: every scope drawn at the size the layout gives it) and a probe
  // that records where the panels are.
  std::string page = test_support::ReadText(kWeb + "/index.html");
  page = std::regex_replace(page, std::regex("\"/monitor.css\""), "\"monitor.css\"");
  page = std::regex_replace(page, std::regex("<script src=\"/monitor.js\"></script>"),
                            "<script src=\"fake.js\"></script><script src=\"monitor.js\"></script>");
  page = std::regex_replace(page, std::regex("</body>"), "<script src=\"probe.js\"></script></body>");
  test_support::WriteText(dir / "index.html", page);
  for (const char* asset : {"monitor.css", "monitor.js"}) {
    test_support::WriteText(dir / asset, test_support::ReadText(kWeb + "/" + asset));
  }
  test_support::WriteText(dir / "fake.js", R"js(window.fetch = async (url) => {
  if (!String(url).startsWith("/api/series")) throw new Error("no server");
  const t = [...Array(50).keys()].map((i) => i * 0.01);
  const c = { seq: t.map((x, i) => i + 1), t };
  for (const k of ["d0", "r0", "command0", "position0", "force0", "d1", "r1", "command1",
                   "position1", "force1"]) c[k] = t.map((x) => Math.sin(7 * x));
  return { json: async () => ({ slots: 2, actuators: 2, generation: 1, reset: true, columns: c }) };
};
)js");
  test_support::WriteText(dir / "probe.js", R"js(window.addEventListener("load", () => setTimeout(() => {
  const b = document.body;
  for (const id of ["meters-panel", "scopes-panel"]) {
    const r = document.getElementById(id).getBoundingClientRect();
    b.setAttribute("data-" + id + "-top", r.top.toFixed(0));
    b.setAttribute("data-" + id + "-bottom", r.bottom.toFixed(0));
  }
  b.setAttribute("data-height", window.innerHeight);
}, 500));
)js");
  const auto [status, dom] = RunCommand(
      chromium + " --headless --no-sandbox --disable-gpu --no-first-run --user-data-dir=" +
          (dir / "profile").string() + " --window-size=1400,1000 --virtual-time-budget=3000 "
          "--dump-dom file://" + (dir / "index.html").string(),
      90, false);
  ASSERT_EQ(status, 0) << dom;
  const double height = Attribute(dom, "data-height");
  ASSERT_GT(height, 0.0) << dom.substr(0, 2000);
  EXPECT_LT(Attribute(dom, "data-meters-panel-top"), height);
  EXPECT_GE(Attribute(dom, "data-meters-panel-top"), 0.0);
  EXPECT_LT(Attribute(dom, "data-scopes-panel-top"), height);
  EXPECT_LE(Attribute(dom, "data-scopes-panel-bottom"), height)
      << "the scopes end below the first screen (" << height << " px)";
}

}  // namespace
}  // namespace hybridtest::testing
