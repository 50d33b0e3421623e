#pragma once
// Headless Chromium for the monitor's page tests (Debian's `chromium`; the tests skip with a
// message where it is absent).
#include <string>

#include "support/run_command.h"

namespace hybridtest::testing {

// The first of chromium, chromium-browser, chromium-headless-shell on PATH, or "".
inline std::string FindChromium() {
  for (const char* name : {"chromium", "chromium-browser", "chromium-headless-shell"}) {
    const auto [status, out] = RunCommand(std::string("sh -c 'command -v ") + name + "'", 10, false);
    if (status == 0 && !out.empty()) return out.substr(0, out.find('\n'));
  }
  return "";
}

}  // namespace hybridtest::testing
