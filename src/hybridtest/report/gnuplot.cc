#include "hybridtest/report/gnuplot.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/core.h>

#include "hybridtest/common/error.h"

extern char** environ;

namespace hybridtest::report {
namespace {

// A uniquely named temporary file, removed when this goes out of scope.
class TempFile {
 public:
  explicit TempFile(const std::string& suffix) {
    std::string pattern =
        (std::filesystem::temp_directory_path() / ("hybridtest-XXXXXX" + suffix)).string();
    const int fd = mkstemps(pattern.data(), static_cast<int>(suffix.size()));
    if (fd < 0) {
      throw IoError("gnuplot: cannot create a temporary file " + pattern + ": " +
                    std::strerror(errno) + "; check TMPDIR");
    }
    ::close(fd);
    path_ = pattern;
  }
  ~TempFile() {
    std::error_code ignored;
    std::filesystem::remove(path_, ignored);
  }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

std::string ReadAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The last max_chars characters of text, marked as cut when longer.
std::string Tail(const std::string& text, std::size_t max_chars) {
  if (text.size() <= max_chars) return text;
  return "[...]" + text.substr(text.size() - max_chars);
}

}  // namespace

void RunGnuplot(const std::string& script, const std::string& program) {
  TempFile script_file(".gp");
  TempFile error_file(".err");
  {
    std::ofstream out(script_file.path(), std::ios::binary);
    out << script;
    if (!out) throw IoError("gnuplot: cannot write the script to " + script_file.path());
  }

  // Child: stdin from /dev/null, stdout discarded, stderr into error_file.
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, error_file.path().c_str(),
                                   O_WRONLY | O_TRUNC, 0);
  std::string arg0 = program;
  std::string arg1 = script_file.path();
  char* argv[] = {arg0.data(), arg1.data(), nullptr};
  pid_t pid = 0;
  const int spawn_error = posix_spawnp(&pid, program.c_str(), &actions, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  const std::string install_hint =
      "; figures need gnuplot with the pngcairo and svg terminals: install gnuplot-nox "
      "(apt-get install gnuplot-nox, or scripts/install-deps.sh)";
  if (spawn_error != 0) {
    throw IoError("cannot run gnuplot ('" + program + "'): " + std::strerror(spawn_error) +
                  install_hint);
  }

  // Wait for it; a signal interrupting the wait is not a failure of gnuplot.
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) {
      throw IoError(std::string("gnuplot: waitpid failed: ") + std::strerror(errno));
    }
  }
  const std::string errors = Tail(ReadAll(error_file.path()), 4000);
  if (WIFEXITED(status) && WEXITSTATUS(status) == 127) {
    throw IoError("cannot run gnuplot ('" + program + "'): exit status 127" + install_hint);
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    const std::string how = WIFEXITED(status)
                                ? fmt::format("exited with status {}", WEXITSTATUS(status))
                                : fmt::format("was killed by signal {}", WTERMSIG(status));
    throw IoError(fmt::format("gnuplot ('{}') {} on a generated script; its stderr:\n{}", program,
                              how, errors));
  }
}

std::vector<std::string> RenderFigures(const std::vector<PlotFigure>& figures,
                                       const std::string& out_dir,
                                       const GnuplotOptions& options) {
  std::error_code error;
  std::filesystem::create_directories(out_dir, error);
  if (error) {
    throw IoError("cannot create the figure directory " + out_dir + ": " + error.message());
  }
  const GnuplotScript script = MakeGnuplotScript(figures, out_dir, options.script);
  if (script.outputs.empty()) return {};
  RunGnuplot(script.text, options.program);
  for (const std::string& path : script.outputs) {
    if (!std::filesystem::exists(path) || std::filesystem::file_size(path) == 0) {
      throw IoError("gnuplot exited normally but did not write " + path +
                    "; check that the directory is writable and that gnuplot has the pngcairo "
                    "and svg terminals (gnuplot -e 'set terminal')");
    }
  }
  return script.outputs;
}

}  // namespace hybridtest::report
