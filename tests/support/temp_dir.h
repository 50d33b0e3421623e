#pragma once
// Scratch files for tests: a fresh directory per test process, and whole-file text I/O.
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace hybridtest::test_support {

// The directory tests write their scratch files in: $TMPDIR when it is set (scripts/test.sh
// points it at a fresh directory in /dev/shm and removes it afterwards), else /dev/shm when it
// is a writable directory (a tmpfs: a physical run syncs its journal at every row, and on a
// disk those syncs are most of a test's time, 70 s instead of 8 s for a 10,000-row emulated
// run), else the system's temporary directory.
inline std::filesystem::path ScratchBase() {
  static const std::filesystem::path base = [] {
    std::error_code error;
    if (const char* tmp = std::getenv("TMPDIR");
        tmp != nullptr && *tmp != '\0' && std::filesystem::is_directory(tmp, error)) {
      return std::filesystem::path(tmp);
    }
    if (std::filesystem::is_directory("/dev/shm", error) && ::access("/dev/shm", W_OK) == 0) {
      return std::filesystem::path("/dev/shm");
    }
    return std::filesystem::temp_directory_path();
  }();
  return base;
}

// <scratch>/hybridtest_<name>_<pid>, emptied if it was left over, then created. The pid keeps
// the test processes that CTest runs in parallel apart.
inline std::filesystem::path FreshTempDir(const std::string& name) {
  const std::filesystem::path dir = ScratchBase() /
                                    ("hybridtest_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// The whole file, bytes as they are ("" if it cannot be opened).
inline std::string ReadText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Writes `text` as the whole file, bytes as they are.
inline void WriteText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

}  // namespace hybridtest::test_support
