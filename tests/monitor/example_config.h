#pragma once
// An example's config copied into a test's folder with edits (a shorter duration, ...) and
// the files it names made absolute, for the monitor's tests. Fails the test when an edit no
// longer finds what it replaces (the example changed).
#include <gtest/gtest.h>

#include <regex>
#include <string>
#include <utility>
#include <vector>

#include "integration/resume_support.h"
#include "support/temp_dir.h"

namespace hybridtest::testing {

// examples/<example>/<file> with each regex `from` replaced by `to`, and `file: F` / `config:
// F` for each F of `relative` made absolute; written to dir/<file>.
inline fs::path WriteExampleConfig(const fs::path& dir, const std::string& example,
                                   const std::string& file,
                                   std::vector<std::pair<std::string, std::string>> edits,
                                   const std::vector<std::string>& relative) {
  const std::string folder = kSource + "/examples/" + example + "/";
  for (const std::string& f : relative) edits.emplace_back(": " + f, ": " + folder + f);
  std::string config = test_support::ReadText(folder + file);
  for (const auto& [from, to] : edits) {
    const std::string edited = std::regex_replace(config, std::regex(from), to);
    EXPECT_NE(edited, config) << file << " no longer has " << from;
    config = edited;
  }
  test_support::WriteText(dir / file, config);
  return dir / file;
}

}  // namespace hybridtest::testing
