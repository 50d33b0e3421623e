// The compiled-model cache is private and loads only what it built (issue 45 item 2, break 3):
// a cache directory others may write is refused; a library that is not the one recorded when
// it was built (replaced at the predictable path) is refused before dlopen, so its
// constructors never run; a library writable by its group likewise; a library without its
// record (an older cache) is built again over it, never loaded. Before, each of these was
// loaded (the planted library's constructor ran).
#include <dlfcn.h>
#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/stat.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "hybridtest/common/error.h"
#include "hybridtest/models/catalogue.h"
#include "hybridtest/symbolic/compiled_model.h"

namespace hybridtest::symbolic {
namespace {

namespace fs = std::filesystem;

fs::path UseOwnCache() {
  const auto* info = testing::UnitTest::GetInstance()->current_test_info();
  const fs::path dir = testing::TempDir() + "/cache-" + info->name();
  fs::remove_all(dir);
  setenv("HYBRIDTEST_CACHE_DIR", dir.c_str(), 1);
  unsetenv("CC");
  return dir;
}

models::BuiltModel Rotor() {
  return models::BuildModel("rotor", 3, models::DefaultParameters("rotor", 3));
}

std::string ErrorOf(const models::BuiltModel& built) {
  try {
    CompileModel(built.model, built.name);
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

// A shared library whose constructor creates the file named by $HYBRIDTEST_TEST_MARKER.
fs::path PlantedLibrary(const fs::path& dir) {
  const fs::path c = dir / "planted.c", so = dir / "planted.so";
  std::ofstream(c) << "#include <stdio.h>\n#include <stdlib.h>\n"
                      "__attribute__((constructor)) static void planted(void) {\n"
                      "  const char* p = getenv(\"HYBRIDTEST_TEST_MARKER\");\n"
                      "  FILE* f = p ? fopen(p, \"w\") : 0;\n  if (f) fclose(f);\n}\n"
                      "int hybridtest_rhs_n = 0;\n";
  const std::string command = "cc -shared -fPIC -o " + so.string() + " " + c.string();
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  return so;
}

TEST(ModelCache, IsCreatedPrivate) {
  const fs::path dir = UseOwnCache();
  CompileReport report;
  CompileModel(Rotor().model, "rotor", &report);
  struct stat st {};
  ASSERT_EQ(stat(dir.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0700u);
  ASSERT_EQ(stat(report.library.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0077, 0u);
  EXPECT_TRUE(fs::exists(fs::path(report.library).replace_extension(".sha256")));
}

TEST(ModelCache, ADirectoryOthersMayWriteIsRefused) {
  const fs::path dir = UseOwnCache();
  fs::create_directories(dir);
  fs::permissions(dir, fs::perms::all);  // 0777
  const std::string error = ErrorOf(Rotor());
  EXPECT_NE(error.find("refusing the cache of compiled models " + dir.string()), std::string::npos)
      << error;
  EXPECT_NE(error.find("writable by others"), std::string::npos) << error;
  EXPECT_NE(error.find("HYBRIDTEST_CACHE_DIR"), std::string::npos) << error;
}

TEST(ModelCache, AReplacedLibraryIsRefusedBeforeItsConstructorRuns) {
  const fs::path dir = UseOwnCache();
  CompileReport report;
  CompileModel(Rotor().model, "rotor", &report);
  const fs::path planted = PlantedLibrary(fs::path(testing::TempDir()));
  // The planted library does run its constructor when loaded (so the test can fail).
  const fs::path proof = dir.string() + "-proof", marker = dir.string() + "-marker";
  fs::remove(proof);
  fs::remove(marker);
  setenv("HYBRIDTEST_TEST_MARKER", proof.c_str(), 1);
  {
    const fs::path copy = dir.string() + "-copy.so";
    fs::copy_file(planted, copy, fs::copy_options::overwrite_existing);
    void* h = dlopen(copy.c_str(), RTLD_NOW | RTLD_LOCAL);
    ASSERT_NE(h, nullptr) << dlerror();
    dlclose(h);
    ASSERT_TRUE(fs::exists(proof));
  }
  // At the cache's path, owned by this user, mode 0700: refused by its digest.
  setenv("HYBRIDTEST_TEST_MARKER", marker.c_str(), 1);
  fs::copy_file(planted, report.library, fs::copy_options::overwrite_existing);
  fs::permissions(report.library, fs::perms::owner_all);
  const std::string error = ErrorOf(Rotor());
  EXPECT_FALSE(fs::exists(marker)) << "the planted library's constructor ran";
  EXPECT_NE(error.find("digest mismatch"), std::string::npos) << error;
  EXPECT_NE(error.find(report.library), std::string::npos) << error;
  // Without its record (an older hybridtest's cache): built again over it, never loaded.
  fs::remove(fs::path(report.library).replace_extension(".sha256"));
  CompileReport rebuilt;
  CompileModel(Rotor().model, "rotor", &rebuilt);
  EXPECT_FALSE(fs::exists(marker)) << "the planted library's constructor ran";
  EXPECT_FALSE(rebuilt.from_cache);
  EXPECT_TRUE(fs::exists(fs::path(report.library).replace_extension(".sha256")));
  CompileReport again;
  CompileModel(Rotor().model, "rotor", &again);
  EXPECT_TRUE(again.from_cache);
  unsetenv("HYBRIDTEST_TEST_MARKER");
}

TEST(ModelCache, AnEditedSourceIsRefused) {
  UseOwnCache();
  CompileReport report;
  CompileModel(Rotor().model, "rotor", &report);
  std::ofstream(fs::path(report.library).replace_extension(".c"), std::ios::app) << "/* */\n";
  const std::string error = ErrorOf(Rotor());
  EXPECT_NE(error.find("digest mismatch: its source"), std::string::npos) << error;
}

TEST(ModelCache, ALibraryItsGroupMayWriteIsRefused) {
  UseOwnCache();
  CompileReport report;
  CompileModel(Rotor().model, "rotor", &report);
  fs::permissions(report.library, fs::perms::group_write, fs::perm_options::add);
  const std::string error = ErrorOf(Rotor());
  EXPECT_NE(error.find("writable by its group"), std::string::npos) << error;
  // Made private again, it loads from the cache.
  fs::permissions(report.library, fs::perms::group_write, fs::perm_options::remove);
  CompileReport again;
  CompileModel(Rotor().model, "rotor", &again);
  EXPECT_TRUE(again.from_cache);
}

}  // namespace
}  // namespace hybridtest::symbolic
