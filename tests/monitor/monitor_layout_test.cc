// The monitor's layout at 1400 × 1000 (issue 50: the scopes were below the fold): the page's
// own files (src/hybridtest/monitor/web) in headless Chromium at that window size, with a probe
// script appended that records where the meters and the scopes are. Both must start and the
// scopes end within the first screen. Skipped with a message where Debian's `chromium` is
// absent. Without a server the page shows no data: the meters panel holds its "no physical
// actuator" line and the scopes their empty plots (the sizes the layout gives them).
#include <gtest/gtest.h>

#include <regex>
#include <string>

#include "support/run_command.h"
#include "support/temp_dir.h"

namespace hybridtest::testing {
namespace {

const std::string kWeb = std::string(HYBRIDTEST_SOURCE_DIR) + "/src/hybridtest/monitor/web";

std::string FindChromiumBinary() {
  for (const char* name : {"chromium", "chromium-browser", "chromium-headless-shell"}) {
    const auto [status, out] = RunCommand(std::string("sh -c 'command -v ") + name + "'", 10, false);
    if (status == 0 && !out.empty()) return out.substr(0, out.find('\n'));
  }
  return "";
}

double Attribute(const std::string& dom, const std::string& name) {
  std::smatch m;
  if (!std::regex_search(dom, m, std::regex(name + "=\"(-?[0-9.]+)\""))) return -1.0;
  return std::stod(m[1].str());
}

TEST(MonitorLayout, MetersAndScopesAreOnTheFirstScreenAt1400x1000) {
  const std::string chromium = FindChromiumBinary();
  if (chromium.empty()) GTEST_SKIP() << "chromium not found (scripts/install-deps.sh)";
  const auto dir = test_support::FreshTempDir("monitor_layout");
  std::string page = test_support::ReadText(kWeb + "/index.html");
  for (const std::string asset : {"/monitor.css", "/monitor.js", "/uplot.css", "/uplot.js"}) {
    page = std::regex_replace(page, std::regex("\"" + asset + "\""), "\"" + asset.substr(1) + "\"");
  }
  const std::string probe =
      "<script>window.addEventListener('load', () => { const b = document.body;"
      " for (const id of ['meters-panel', 'scopes-panel']) {"
      "  const r = document.getElementById(id).getBoundingClientRect();"
      "  b.setAttribute('data-' + id + '-top', r.top.toFixed(0));"
      "  b.setAttribute('data-' + id + '-bottom', r.bottom.toFixed(0)); }"
      " b.setAttribute('data-height', window.innerHeight); });</script>\n</body>";
  page = std::regex_replace(page, std::regex("</body>"), probe);
  test_support::WriteText(dir / "index.html", page);
  for (const char* asset : {"monitor.css", "monitor.js"}) {
    test_support::WriteText(dir / asset, test_support::ReadText(kWeb + "/" + asset));
  }
  const auto [status, dom] = RunCommand(
      chromium + " --headless --no-sandbox --disable-gpu --no-first-run --user-data-dir=" +
          (dir / "profile").string() + " --window-size=1400,1000 --virtual-time-budget=2000 "
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
