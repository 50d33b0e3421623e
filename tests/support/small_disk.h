#pragma once
// A small disk for a test: `body` runs in a forked child in a private mount namespace in
// which `mount_point` is a fresh tmpfs of `bytes`; the string it returns comes back to the
// test. The child is a new user and mount namespace (as `unshare -rm` makes), so no root is
// needed where the kernel allows user namespaces; where it does not, nullopt (the caller
// skips). The body must not throw (catch inside and return the message); a child that fails
// otherwise returns a message saying so (which the test's expectations then reject).
#include <fcntl.h>
#include <sched.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "support/temp_dir.h"

namespace hybridtest::test_support {

namespace small_disk_internal {
inline bool WriteProc(const char* path, const std::string& text) {
  const int fd = ::open(path, O_WRONLY);
  if (fd < 0) return false;
  const bool ok = ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
  ::close(fd);
  return ok;
}
}  // namespace small_disk_internal

inline std::optional<std::string> RunOnSmallDisk(const std::filesystem::path& mount_point,
                                                 std::size_t bytes,
                                                 const std::function<std::string()>& body) {
  namespace fs = std::filesystem;
  fs::create_directories(mount_point);
  const fs::path answer = mount_point.parent_path() / (mount_point.filename().string() + ".answer");
  fs::remove(answer);
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) return std::nullopt;
  if (pid == 0) {
    const uid_t uid = ::getuid();
    const gid_t gid = ::getgid();
    if (::unshare(CLONE_NEWUSER | CLONE_NEWNS) != 0) ::_exit(77);
    using small_disk_internal::WriteProc;
    WriteProc("/proc/self/setgroups", "deny");
    if (!WriteProc("/proc/self/uid_map", "0 " + std::to_string(uid) + " 1") ||
        !WriteProc("/proc/self/gid_map", "0 " + std::to_string(gid) + " 1")) {
      ::_exit(77);
    }
    // Private: the tmpfs must not show in the parent's namespace.
    if (::mount(nullptr, "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0) ::_exit(77);
    const std::string size = "size=" + std::to_string(bytes);
    if (::mount("tmpfs", mount_point.c_str(), "tmpfs", 0, size.c_str()) != 0) ::_exit(77);
    WriteText(answer, body());
    ::_exit(0);
  }
  int status = 0;
  if (::waitpid(pid, &status, 0) != pid) return "the small-disk child was lost";
  if (WIFEXITED(status) && WEXITSTATUS(status) == 77) return std::nullopt;  // no namespace here
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    return "the small-disk child failed (wait status " + std::to_string(status) + ")";
  }
  return ReadText(answer);
}

}  // namespace hybridtest::test_support
