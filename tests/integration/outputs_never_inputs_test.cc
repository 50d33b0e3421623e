// No command writes over a file it reads (issue 33, item 3): `report`, `export`, `plot` and
// `compare` onto the journal, its sidecar or a symlink to them, onto a FIFO or a device, and a
// config named like the run's lock file, all exit 2 and leave every file byte-identical.
#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <chrono>
#include <filesystem>

#include "integration/child_process.h"

namespace hybridtest {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const std::string kSource = HYBRIDTEST_SOURCE_DIR;

// `hybridtest <args>` to its end (bounded); returns {status, output}.
std::pair<int, std::string> Hybridtest(const std::vector<std::string>& args, const fs::path& log,
                                       double timeout = 60.0) {
  std::vector<std::string> argv{HYBRIDTEST_BINARY};
  argv.insert(argv.end(), args.begin(), args.end());
  Child child(argv, log);
  const int status = child.WaitExit(timeout);
  return {status, child.output()};
}

// One short numerical run per test process (0.2 s of the paper's rotor, all numerical).
class OutputsNeverInputs : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = test_support::FreshTempDir("outputs_never_inputs");
    test_support::WriteText(dir_ / "k.yaml",
                            "model: {name: rotor, blades: 3}\n"
                            "integrator: {tableau: heun, dt: 0.001}\n"
                            "duration: 0.2\n");
    const auto [status, out] = Hybridtest(
        {"simulate", (dir_ / "k.yaml").string(), "--out", (dir_ / "k.csv").string(), "--quiet"},
        dir_ / "simulate.log");
    ASSERT_EQ(status, 0) << out;
  }
  void SetUp() override {
    csv_ = test_support::ReadText(dir_ / "k.csv");
    sidecar_ = test_support::ReadText(dir_ / "k.meta.json");
    config_ = test_support::ReadText(dir_ / "k.yaml");
    ASSERT_FALSE(csv_.empty());
    ASSERT_FALSE(sidecar_.empty());
  }
  // Refused with exit 2 and a message naming `what`; every file of the run unchanged.
  void ExpectRefused(const std::vector<std::string>& args, const std::string& what) {
    const auto start = std::chrono::steady_clock::now();
    const auto [status, out] = Hybridtest(args, dir_ / "refused.log", 20.0);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cout << "[ " << args[0] << " refused in " << seconds << " s ]\n";
    EXPECT_EQ(status, 2) << out;
    EXPECT_THAT(out, HasSubstr(what));
    EXPECT_EQ(test_support::ReadText(dir_ / "k.csv"), csv_);
    EXPECT_EQ(test_support::ReadText(dir_ / "k.meta.json"), sidecar_);
    EXPECT_EQ(test_support::ReadText(dir_ / "k.yaml"), config_);
  }
  static std::string P(const std::string& name) { return (dir_ / name).string(); }

  static fs::path dir_;
  std::string csv_, sidecar_, config_;
};
fs::path OutputsNeverInputs::dir_;

TEST_F(OutputsNeverInputs, ReportOntoTheJournalItsSidecarOrASymlinkIsRefused) {
  ExpectRefused({"report", P("k.csv"), "--out", P("k.csv")}, "the journal of");
  ExpectRefused({"report", P("k.csv"), "--out", P("k.meta.json")}, "the sidecar of");
  fs::remove(dir_ / "link.csv");
  fs::create_symlink(dir_ / "k.csv", dir_ / "link.csv");
  ExpectRefused({"report", P("k.csv"), "--out", P("link.csv")}, "the journal of");
  // The run's config (recorded in its sidecar) and the run compared against.
  ExpectRefused({"report", P("k.csv"), "--out", P("k.yaml")}, "the config file of");
  ExpectRefused({"report", P("k.csv"), "--against", P("k.csv"), "--out", P("k.meta.json")},
                "the sidecar of");
}

TEST_F(OutputsNeverInputs, ExportOntoAnInputIsRefused) {
  ExpectRefused({"export", P("k.csv"), "--csv", P("k.csv")}, "--csv");
  ExpectRefused({"export", P("k.csv"), "--hdf5", P("k.meta.json")}, "the sidecar of");
  ExpectRefused({"export", P("k.csv"), "--csv", P("link2.csv"), "--hdf5", P("link2.csv")},
                "name the same file");
  EXPECT_FALSE(fs::exists(dir_ / "link2.csv"));
}

TEST_F(OutputsNeverInputs, FifosAndDevicesAreRefusedWithoutBlocking) {
  fs::remove(dir_ / "pipe");
  ASSERT_EQ(::mkfifo(P("pipe").c_str(), 0600), 0);
  // Nobody reads the FIFO: opening it for writing would block for ever.
  ExpectRefused({"report", P("k.csv"), "--out", P("pipe")}, "is a FIFO");
  ExpectRefused({"export", P("k.csv"), "--csv", P("pipe")}, "is a FIFO");
  ExpectRefused({"report", P("k.csv"), "--out", "/dev/null"}, "is a device");
  ExpectRefused({"export", P("k.csv"), "--hdf5", "/dev/null"}, "is a device");
}

TEST_F(OutputsNeverInputs, PlotAndCompareNeverWriteOverARun) {
  ExpectRefused({"plot", P("k.csv"), "--out", P("k.csv")}, "not a directory");
  // A run called comparison.csv compared into its own directory.
  const fs::path sub = dir_ / "cmp";
  fs::create_directories(sub);
  fs::copy_file(dir_ / "k.csv", sub / "comparison.csv", fs::copy_options::overwrite_existing);
  fs::copy_file(dir_ / "k.meta.json", sub / "comparison.meta.json",
                fs::copy_options::overwrite_existing);
  const std::string before = test_support::ReadText(sub / "comparison.csv");
  ExpectRefused({"compare", (sub / "comparison.csv").string(), P("k.csv"), "--out", sub.string()},
                "the journal of run A");
  EXPECT_EQ(test_support::ReadText(sub / "comparison.csv"), before);
}

TEST_F(OutputsNeverInputs, AConfigNamedLikeTheLockIsNeverDeleted) {
  // The run's lock for --out x/k2.csv is x/k2.lock: here that is the config itself.
  const fs::path sub = dir_ / "lockname";
  fs::create_directories(sub);
  test_support::WriteText(sub / "k2.lock", config_);
  const auto [status, out] =
      Hybridtest({"simulate", (sub / "k2.lock").string(), "--out", (sub / "k2.csv").string(),
                  "--quiet"},
                 dir_ / "lockname.log");
  EXPECT_EQ(status, 2) << out;
  EXPECT_THAT(out, HasSubstr("not a hybridtest lock file"));
  EXPECT_EQ(test_support::ReadText(sub / "k2.lock"), config_);
  EXPECT_FALSE(fs::exists(sub / "k2.csv"));
}

}  // namespace
}  // namespace hybridtest
