// The name rule through the real binary (issue 45, contract: "a model file whose names carry
// C, Python or LaTeX is refused at its line by check-model, equations, compile-model and every
// run"). Each front reads the file through the one loader; each is asserted once here.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "support/run_command.h"
#include "support/temp_dir.h"

namespace hybridtest {
namespace {

namespace fs = std::filesystem;

std::pair<int, std::string> Hybridtest(const std::string& args) {
  return testing::RunCommand(std::string(HYBRIDTEST_BINARY) + " " + args, 300, true);
}

fs::path TempDir() {
  static const fs::path dir = test_support::FreshTempDir("modelfile-names");
  return dir;
}

// A pendulum whose names carry code: C on line 5, or Python / LaTeX.
fs::path Write(const std::string& file, const std::string& coordinate, const std::string& name) {
  const fs::path path = TempDir() / file;
  std::ofstream(path) << "name: " << name << "\n"                           // 1
                      << "parameters:\n  l: {value: 1.0, unit: m}\n"         // 2-3
                      << "coordinates:\n"                                    // 4
                      << "  - {name: " << coordinate << ", unit: rad}\n"     // 5
                      << "frames:\n  - {name: A, parent: N, axis: z, angle: th}\n"
                      << "points:\n  - {name: P, from: O, frame: A, position: [l, 0, 0]}\n"
                      << "particles:\n  - {name: bob, point: P, mass: 2}\n";
  return path;
}

TEST(ModelFileNamesCliTest, EveryCommandRefusesANameThatCarriesCode) {
  const fs::path c = Write("c.yaml", "'th */ int evil; /*'", "p");
  const fs::path py = Write("py.yaml", "th", "\"p\\\"\\\"\\\"\\nimport os\"");
  const fs::path tex = Write("tex.yaml", "th", "'\\input{/etc/passwd}'");
  const fs::path config = TempDir() / "run.yaml";
  std::ofstream(config) << "model: {file: c.yaml, compiled: true}\n"
                           "integrator: {tableau: heun, dt: 0.001}\nduration: 0.01\n";
  setenv("HYBRIDTEST_CACHE_DIR", (TempDir() / "cache").c_str(), 1);
  struct Case {
    std::string args;
    fs::path file;
    int line;
  };
  const std::vector<Case> cases = {
      {"check-model " + c.string(), c, 5},
      {"check-model " + py.string(), py, 1},
      {"check-model " + tex.string(), tex, 1},
      {"equations " + c.string() + " --format c", c, 5},
      {"equations " + py.string() + " --format sympy", py, 1},
      {"equations " + tex.string() + " --format latex", tex, 1},
      {"equations " + c.string() + " --format markdown", c, 5},
      {"compile-model " + c.string(), c, 5},
      {"simulate " + config.string() + " --out " + (TempDir() / "out.csv").string(), c, 5},
  };
  for (const Case& k : cases) {
    const auto [status, out] = Hybridtest(k.args);
    EXPECT_EQ(status, 2) << k.args << "\n" << out;
    EXPECT_NE(out.find(fmt::format("{}:{}:", k.file.string(), k.line)), std::string::npos)
        << k.args << "\n" << out;
    EXPECT_NE(out.find("not a valid name"), std::string::npos) << k.args << "\n" << out;
  }
  // Nothing was compiled: the cache holds no library.
  if (fs::exists(TempDir() / "cache")) {
    for (const auto& entry : fs::directory_iterator(TempDir() / "cache")) {
      EXPECT_NE(entry.path().extension(), ".so") << entry.path();
    }
  }
}

}  // namespace
}  // namespace hybridtest
