// The page's axis helpers under node (tests/monitor/monitor_axes_test.js): labels below zero
// keep their minus sign, ticks at 1–2–5 steps, axes wide enough. Skipped without node
// (Debian's `nodejs`, scripts/install-deps.sh).
#include <gtest/gtest.h>

#include "integration/resume_support.h"
#include "support/run_command.h"

namespace hybridtest::testing {
namespace {

TEST(MonitorAxes, LabelsKeepTheirSignUnderNode) {
  const auto [found, where] = RunCommand("sh -c 'command -v node'", 10, false);
  if (found != 0 || where.empty()) {
    GTEST_SKIP() << "node not found: the page's axis test needs Debian's `nodejs` "
                    "(scripts/install-deps.sh)";
  }
  const auto [status, out] =
      RunCommand("node " + kSource + "/tests/monitor/monitor_axes_test.js " + kSource, 60, false);
  EXPECT_EQ(status, 0) << out;
  EXPECT_NE(out.find("monitor axes: ok"), std::string::npos) << out;
}

}  // namespace
}  // namespace hybridtest::testing
