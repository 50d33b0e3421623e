// The README's commands build what they run: the main job (scripts/main-job.sh) builds only
// the hybridtest binary and installs only its packages; the test command (scripts/test.sh)
// builds and installs everything, the test suite included. Checked through the scripts'
// --print mode, which prints the commands instead of running them.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "support/run_command.h"

namespace hybridtest {
namespace {

const std::string kSource = HYBRIDTEST_SOURCE_DIR;

std::string Script(const std::string& name) {
  std::ifstream in(kSource + "/scripts/" + name);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string RunScript(const std::string& args) {
  const auto [status, out] = testing::RunCommand("bash " + kSource + "/scripts/" + args);
  EXPECT_EQ(status, 0) << args << ": " << out;
  return out;
}

TEST(MainJobScripts, TheMainJobBuildsOnlyTheBinary) {
  EXPECT_NE(Script("main-job.sh").find("\nscripts/build.sh --app\n"), std::string::npos);
  const std::string build = RunScript("build.sh --app --print");
  EXPECT_NE(build.find("scripts/install-deps.sh --app\n"), std::string::npos) << build;
  // The binary and the example FMUs (examples/fmi/), nothing of the test suite.
  EXPECT_NE(build.find("--target hybridtest hybridtest_example_fmus\n"), std::string::npos)
      << build;
  const std::string packages = RunScript("install-deps.sh --app --print");
  for (const char* test_only : {"libgtest-dev", "libbenchmark-dev", "clang", "python3-sympy"}) {
    EXPECT_EQ(packages.find(test_only), std::string::npos) << test_only;
  }
  for (const char* needed : {"cmake", "libhdf5-dev", "libmodbus-dev", "gnuplot-nox"}) {
    EXPECT_NE(packages.find(needed), std::string::npos) << needed;
  }
}

TEST(MainJobScripts, TheTestCommandStillBuildsTheTests) {
  EXPECT_NE(Script("test.sh").find("\nscripts/build.sh\n"), std::string::npos);
  const std::string build = RunScript("build.sh --print");
  EXPECT_EQ(build.find("--target"), std::string::npos) << build;
  EXPECT_EQ(build.find("BUILD_TESTS=OFF"), std::string::npos) << build;
  const std::string packages = RunScript("install-deps.sh --print");
  for (const char* needed : {"libgtest-dev", "libbenchmark-dev", "clang", "python3-sympy",
                             "gnuplot-nox"}) {
    EXPECT_NE(packages.find(needed), std::string::npos) << needed;
  }
  EXPECT_NE(testing::RunCommand("bash " + kSource + "/scripts/build.sh --nonsense").first, 0);
}

}  // namespace
}  // namespace hybridtest
