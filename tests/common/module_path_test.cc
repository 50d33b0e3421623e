// FindModule (common/module_path.h): the build tree's module directory is searched only by code
// that is itself a file of that build tree.
#include "hybridtest/common/module_path.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace hybridtest {
namespace {

namespace fs = std::filesystem;

constexpr const char* kModule = "hybridtest_no_such_module.so";
constexpr const char* kEnv = "HYBRIDTEST_TEST_NO_SUCH_MODULE";

// Prints what FindModule searched (run by the test below from a copy of this program).
TEST(ModulePath, DISABLED_PrintSearched) {
  std::printf("searched: %s\n", FindModule(kModule, kEnv).searched.c_str());
}

TEST(ModulePath, TheBuildTreeIsSearchedOnlyFromIt) {
  ::unsetenv(kEnv);
  const std::string here = FindModule(kModule, kEnv).searched;
  const fs::path self = fs::read_symlink("/proc/self/exe");
  // From the build tree (this program): the build tree's apps/hybridtest/ is among the places.
  const fs::path build_dir = self.parent_path().parent_path() / "apps" / "hybridtest";
  EXPECT_NE(here.find((build_dir / kModule).string()), std::string::npos) << here;

  // A copy of this program outside the build tree stands for a program linking the installed
  // library: it does not search the build tree.
  const fs::path dir =
      fs::temp_directory_path() / ("hybridtest-module-path-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path copy = dir / "copy";
  fs::copy_file(self, copy, fs::copy_options::overwrite_existing);
  const std::string out = (dir / "out.txt").string();
  const std::string command = copy.string() +
                              " --gtest_also_run_disabled_tests"
                              " --gtest_filter=ModulePath.DISABLED_PrintSearched > " +
                              out + " 2>&1";
  const int status = std::system(command.c_str());
  std::ifstream in(out);
  std::ostringstream read;
  read << in.rdbuf();
  const std::string text = read.str();
  fs::remove_all(dir);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << text;
  ASSERT_NE(text.find("searched: "), std::string::npos) << text;
  EXPECT_EQ(text.find((build_dir / kModule).string()), std::string::npos) << text;
  EXPECT_NE(text.find((dir / kModule).string()), std::string::npos) << text;  // beside itself
}

}  // namespace
}  // namespace hybridtest
