// See sympy_check.h.
#include "sympy_check.h"

#include <fmt/core.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstring>
#include <iterator>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <nlohmann/json.hpp>

#include "hybridtest/common/error.h"

namespace hybridtest::app {
namespace {
std::string Quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// Runs `command` through the shell; returns its standard output and sets `status`.
std::string Capture(const std::string& command, int* status) {
  std::string out;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) {
    *status = -1;
    return out;
  }
  char buffer[4096];
  std::size_t got = 0;
  while ((got = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) out.append(buffer, got);
  *status = ::pclose(pipe);
  return out;
}

// Runs `command` (a script of check-model's SymPy half), at most `timeout_s` seconds if > 0.
// Returns its standard output, with `status` set and `errors` the last lines of its standard
// error. Throws Error if the time ran out.
std::string RunScript(const std::string& command, double timeout_s, const std::string& model_file,
                      int* status, std::string* errors) {
  const std::filesystem::path errors_file = std::filesystem::temp_directory_path() /
      fmt::format("hybridtest-check-model-{}.err", ::getpid());
  const std::string limit = timeout_s > 0.0 ? fmt::format("timeout {:g} ", timeout_s) : "";
  const std::string out =
      Capture(fmt::format("{}{} 2>{}", limit, command, Quote(errors_file.string())), status);
  {
    // (Through rdbuf: GCC 12 flags istreambuf_iterator's inlined loop with a
    // -Wnull-dereference false positive inside <streambuf>.)
    std::ifstream err(errors_file);
    std::ostringstream text;
    if (err) text << err.rdbuf();
    *errors = LastLines(text.str(), 8);
  }
  std::filesystem::remove(errors_file);
  if (timeout_s > 0.0 && WIFEXITED(*status) && WEXITSTATUS(*status) == 124) {
    throw Error(fmt::format("check-model's SymPy half did not finish within {:g} s on {}; raise "
                            "--sympy-timeout, compare fewer states (--sympy-states) or skip it "
                            "with --no-sympy", timeout_s, model_file));
  }
  return out;
}
}  // namespace

std::string DescribeStatus(int status) {
  if (status == -1) return "it could not be started";
  if (WIFEXITED(status)) {
    const int code = WEXITSTATUS(status);
    if (code == 127) return "exit code 127 (the interpreter or the script was not found)";
    return fmt::format("exit code {}", code);
  }
  if (WIFSIGNALED(status)) {
    return fmt::format("killed by signal {} ({})", WTERMSIG(status), ::strsignal(WTERMSIG(status)));
  }
  return fmt::format("wait status {}", status);
}

std::string LastLines(const std::string& text, int lines) {
  std::size_t end = text.find_last_not_of(" \n\r\t");
  if (end == std::string::npos) return "(nothing on standard error)";
  std::size_t start = end + 1;
  for (int i = 0; i < lines && start > 0; ++i) {
    const std::size_t nl = text.rfind('\n', start - 1);
    start = nl == std::string::npos ? 0 : nl;
    if (start == 0) break;
  }
  std::string out = text.substr(start, end + 1 - start);
  while (!out.empty() && out.front() == '\n') out.erase(out.begin());
  return out;
}

std::optional<std::string> FindSympyReader(std::string* why) {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  const std::filesystem::path script = exe.parent_path() / "hybridtest_check_model_sympy.py";
  if (!ec && std::filesystem::exists(script)) return script.string();
  *why = fmt::format("the SymPy reader {} is missing (it ships beside the hybridtest binary)",
                     script.string());
  return std::nullopt;
}

std::string FindPythonWithSympy(std::string* why) {
  std::vector<std::string> candidates;
  if (const char* env = std::getenv("HYBRIDTEST_PYTHON"); env != nullptr && *env != '\0') {
    candidates.emplace_back(env);
  }
  candidates.emplace_back("/usr/bin/python3");
  candidates.emplace_back("python3");
  for (const std::string& py : candidates) {
    int status = 0;
    Capture(Quote(py) + " -c 'import sympy, yaml' 2>/dev/null", &status);
    if (status == 0) return py;
  }
  *why = "no python3 with SymPy and PyYAML found (on Debian: apt-get install python3-sympy "
         "python3-yaml)";
  return {};
}

SympyResult RunSympyReader(const std::string& python, const std::string& script,
                           const std::string& model_file, const std::vector<SympyState>& states,
                           double timeout_s) {
  nlohmann::json in = nlohmann::json::array();
  for (const SympyState& s : states) {
    in.push_back({{"t", s.t},
                  {"q", std::vector<double>(s.q.data(), s.q.data() + s.q.size())},
                  {"u", std::vector<double>(s.u.data(), s.u.data() + s.u.size())},
                  {"r", std::vector<double>(s.r.data(), s.r.data() + s.r.size())},
                  {"z", std::vector<double>(s.z.data(), s.z.data() + s.z.size())}});
  }
  const std::filesystem::path states_file = std::filesystem::temp_directory_path() /
      fmt::format("hybridtest-check-model-{}.json", ::getpid());
  std::ofstream(states_file) << in.dump();
  int status = 0;
  std::string errors;
  const std::string out = RunScript(fmt::format("{} -B {} {} {}", Quote(python), Quote(script),
                                                Quote(model_file), Quote(states_file.string())),
                                    timeout_s, model_file, &status, &errors);
  std::filesystem::remove(states_file);
  if (status != 0) {
    throw Error(fmt::format("the SymPy reader {} failed on {}: {}; its message: {}", script,
                            model_file, DescribeStatus(status), errors));
  }
  const nlohmann::json j = nlohmann::json::parse(out, nullptr, false);
  if (j.is_discarded() || !j.contains("M") || !j.contains("g")) {
    throw Error("the SymPy reader printed no JSON {M, g}: " + out.substr(0, 200));
  }
  SympyResult result;
  for (const auto& m : j["M"]) {
    const int n = static_cast<int>(m.size());
    Eigen::MatrixXd M(n, n);
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < n; ++k) M(i, k) = m[i][k].get<double>();
    result.M.push_back(M);
  }
  for (const char* key : {"g", "qdot", "zdot"}) {
    if (!j.contains(key)) throw Error(fmt::format("the SymPy reader printed no '{}'", key));
    const std::string k(key);
    auto& list = k == "g" ? result.g : k == "qdot" ? result.qdot : result.zdot;
    for (const auto& g : j[key]) {
      const std::vector<double> v = g.get<std::vector<double>>();
      list.push_back(Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size())));
    }
  }
  return result;
}

ConstraintCheck RunConstraintCheck(const std::string& python, const std::string& reader_script,
                                   const std::string& model_file, int states, unsigned seed,
                                   double tolerance, double timeout_s) {
  const std::filesystem::path script = std::filesystem::path(reader_script).parent_path() /
                                       "hybridtest_check_constraints_sympy.py";
  std::error_code ec;
  const std::filesystem::path binary = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec || !std::filesystem::exists(script)) {
    throw Error(fmt::format("the SymPy check of the constraints {} is missing (it ships beside "
                            "the hybridtest binary)", script.string()));
  }
  int status = 0;
  std::string errors;
  const std::string out = RunScript(
      fmt::format("{} -B {} --binary {} --model {} --states {} --seed {} --tolerance {:g}",
                  Quote(python), Quote(script.string()), Quote(binary.string()),
                  Quote(model_file), states, seed, tolerance),
      timeout_s, model_file, &status, &errors);
  if (status != 0 && !(WIFEXITED(status) && WEXITSTATUS(status) == 1)) {
    throw Error(fmt::format("the SymPy check of the constraints {} failed on {}: {}; its "
                            "message: {}", script.string(), model_file, DescribeStatus(status),
                            errors));
  }
  ConstraintCheck result;
  result.agree = status == 0;
  result.report = out;
  while (!result.report.empty() && result.report.back() == '\n') result.report.pop_back();
  return result;
}

}  // namespace hybridtest::app
