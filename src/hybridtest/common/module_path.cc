#include "hybridtest/common/module_path.h"

#include <dlfcn.h>

#include <cstdlib>
#include <system_error>
#include <vector>

// Set for this file by src/hybridtest/CMakeLists.txt; the defaults keep it compilable alone.
#ifndef HYBRIDTEST_MODULE_RELATIVE_DIR
#define HYBRIDTEST_MODULE_RELATIVE_DIR "../lib/hybridtest"
#endif
#ifndef HYBRIDTEST_MODULE_INSTALL_DIR
#define HYBRIDTEST_MODULE_INSTALL_DIR "/usr/local/lib/hybridtest"
#endif
#ifndef HYBRIDTEST_MODULE_BUILD_DIR
#define HYBRIDTEST_MODULE_BUILD_DIR ""
#endif

namespace hybridtest {
namespace {

// Whether the code running this function (a test program, the Python module, the hybridtest
// binary) is a file of the build tree that BUILD_DIR belongs to. A library installed from that
// tree and linked into another program is not: for it, the build tree's path (which may be gone,
// or be re-created by someone else) is no place to load code from.
bool RunsFromTheBuildTree() {
  namespace fs = std::filesystem;
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&RunsFromTheBuildTree), &info) == 0 ||
      info.dli_fname == nullptr) {
    return false;
  }
  std::error_code ec;
  const fs::path self = fs::weakly_canonical(fs::path(info.dli_fname), ec);
  const fs::path root =
      fs::weakly_canonical(fs::path(HYBRIDTEST_MODULE_BUILD_DIR).parent_path().parent_path(), ec);
  if (ec || root.empty()) return false;
  const fs::path inside = self.lexically_relative(root);
  return !inside.empty() && *inside.begin() != "..";
}

}  // namespace

ModuleLookup FindModule(const std::string& file_name, const char* env_override) {
  namespace fs = std::filesystem;
  if (const char* env = std::getenv(env_override); env != nullptr && *env != '\0') {
    return {fs::path(env), std::string("$") + env_override + "=" + env};
  }
  std::vector<fs::path> dirs;
  std::error_code no_exe;
  const fs::path exe = fs::read_symlink("/proc/self/exe", no_exe);
  if (!no_exe) {
    dirs.push_back(exe.parent_path());
    dirs.push_back((exe.parent_path() / HYBRIDTEST_MODULE_RELATIVE_DIR).lexically_normal());
  }
  dirs.emplace_back(HYBRIDTEST_MODULE_INSTALL_DIR);
  if (*HYBRIDTEST_MODULE_BUILD_DIR != '\0' && RunsFromTheBuildTree()) {
    dirs.emplace_back(HYBRIDTEST_MODULE_BUILD_DIR);
  }
  ModuleLookup lookup;
  for (const fs::path& dir : dirs) {
    const fs::path candidate = dir / file_name;
    std::error_code absent;
    if (!lookup.found && fs::is_regular_file(candidate, absent)) lookup.found = candidate;
    lookup.searched += (lookup.searched.empty() ? "" : ", ") + candidate.string();
  }
  return lookup;
}

}  // namespace hybridtest
