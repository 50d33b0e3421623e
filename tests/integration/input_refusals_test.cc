// Issue 33, items 8 and 9, end to end: every input that used to hang (a FIFO as any input
// file, rt_plant.rate_hz: 1e12), to run out of memory (a 10⁹-case campaign grid,
// compensated.window: 1e12), to run although documented as refused (a list of 100,001
// values), to be silently accepted or refused with the wrong status, now exits 2 within 5 s
// with a message that names the key or the option. Each case runs the real binary with its
// arguments (no shell), output to a file; a case still running after 5 s is killed and fails.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include "integration/child_process.h"
#include "support/temp_dir.h"

namespace hybridtest {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const std::string kExe = HYBRIDTEST_BINARY;
const std::string kSource = HYBRIDTEST_SOURCE_DIR;

// One directory per test process, with every input file of the cases (made on first use).
const fs::path& Dir();

std::string In(const std::string& name) { return (Dir() / name).string(); }

const std::string kRotor =
    "model: {name: rotor, blades: 3}\nintegrator: {tableau: heun, dt: 0.001}\nduration: 0.01\n";
const std::string kSafety =
    "    safety: {stroke_min: -0.1, stroke_max: 0.1, max_increment: 0.002, force_soft: 250, "
    "force_hard: 300, timeout: 5}\n";

// A physical slot r1 with `transfer` (one line of YAML).
std::string Physical(const std::string& transfer) {
  return kRotor + "substructures:\n  r1:\n    type: physical\n    transfer: " + transfer +
         "\n    setup: {p0: 0.0}\n" + kSafety;
}

// The rotor on the emulated real-time plant with `extra` plant keys, or a compensator.
std::string RealTime(const std::string& transfer) {
  return "model: {name: rotor, blades: 3}\nintegrator: {scheme: alpha-os, dt: 0.001}\n"
         "duration: 0.01\nreal_time: true\n"
         "substructures:\n  r1:\n    type: physical\n    initial_stiffness: 7200\n"
         "    transfer: " + transfer + "\n    safety: defaults\n";
}
const std::string kPlant = "{type: rt_plant, plant: servo_hydraulic, specimen: {mass: 29.13, "
                           "stiffness: 1.19e6, zeta: 0.0097}";

// `n` values "0,1,...", for grids and lists.
std::string Values(long n) {
  std::string list;
  for (long i = 0; i < n; ++i) list += (i ? "," : "") + std::to_string(i);
  return list;
}

const fs::path& Dir() {
  static const fs::path dir = [] {
    const fs::path d = test_support::FreshTempDir("input_refusals");
    auto write = [&](const std::string& name, const std::string& text) {
      test_support::WriteText(d / name, text);
    };
    if (::mkfifo((d / "fifo").c_str(), 0600) != 0) throw std::runtime_error("mkfifo failed");
    write("garbage.csv", "this is not a journal\n\x01\x02\x03 nor a CSV\n");
    write("numerical.yaml", kRotor);
    write("token", "a-token-of-sixteen-bytes-or-more\n");
    write("quiet.yaml", kRotor + "progress: {quiet: maybe}\n");
    write("safety_numerical.yaml",
          kRotor + "substructures:\n  r1:\n    type: numerical\n    safety: {stroke_max: 0.1}\n");
    write("k0_numerical.yaml",
          kRotor + "substructures:\n  r1:\n    type: numerical\n    initial_stiffness: measure\n");
    write("tableau.yaml", "model: {name: double_pendulum}\nduration: 1\nintegrator:\n"
                          "  tableau: {name: mine, b: [0.5, 0.5], c: [0, 1], order: 2}\n"
                          "  dt: 0.01\n");
    write("emulated.yaml",
          Physical("{type: emulated, config: " + kSource + "/examples/rotor/bench-ideal.yaml}"));
    write("bench_unknown.yaml", "bench: {specimen: {type: linear, stiffness: 7200}}\n"
                                "safety: {stroke_max_mm: 100}\n");
    write("emulated_unknown.yaml", Physical("{type: emulated, config: bench_unknown.yaml}"));
    write("fifo_bench.yaml", Physical("{type: emulated, config: fifo}"));
    write("fifo_model.yaml", "model: {file: fifo}\nintegrator: {tableau: heun, dt: 0.001}\n"
                             "duration: 0.01\n");
    write("fifo_token.yaml",
          Physical("{type: remote, address: '127.0.0.1:1', token_file: fifo}"));
    write("campaign_fifo.yaml", "base: numerical.yaml\ntable: fifo\n");
    write("campaign_1e9.yaml", "base: numerical.yaml\ngrid:\n"
                               "  model.parameters.f_w: [" + Values(1000) + "]\n"
                               "  model.parameters.blade1.k_b: [" + Values(1000) + "]\n"
                               "  model.parameters.blade2.k_b: [" + Values(1000) + "]\n");
    write("campaign_1e7.yaml", "base: numerical.yaml\ngrid:\n"
                               "  model.parameters.f_w: [" + Values(10000) + "]\n"
                               "  model.parameters.blade1.k_b: [" + Values(1000) + "]\n");
    write("list.yaml", kRotor + "test: {serials: [" + Values(100001) + "]}\n");
    write("rate.yaml", RealTime(kPlant + ", rate_hz: 1e12}"));
    write("window.yaml",
          RealTime("{type: compensated, method: ats, window: 1e12, inner: " + kPlant + "}}"));
    return d;
  }();
  return dir;
}

struct Case {
  std::string name;                   // the test's name
  std::vector<std::string> args;      // after the binary; "@x" is the file x of Dir()
  std::vector<std::string> expected;  // substrings of the output
};

std::ostream& operator<<(std::ostream& out, const Case& c) { return out << c.name; }

const std::vector<Case>& Cases() {
  static const std::vector<Case> cases{
      // A FIFO (or a directory) as every input file: refused at once.
      {"FifoAsRunConfig", {"run", "@fifo"}, {"fifo", "not a regular file (a FIFO)"}},
      {"DirectoryAsRunConfig", {"run", "@"}, {"(a directory)"}},
      {"FifoAsBenchFile", {"run", "@fifo_bench.yaml", "--out", "@o.csv"}, {"fifo", "a FIFO"}},
      {"FifoAsModelFile", {"run", "@fifo_model.yaml", "--out", "@o.csv"}, {"fifo", "a FIFO"}},
      {"FifoAsConfigTokenFile",
       {"run", "@fifo_token.yaml", "--out", "@o.csv"},
       {"substructures.r1.transfer.token_file", "a FIFO"}},
      {"FifoAsCampaignTable",
       {"campaign", "@campaign_fifo.yaml", "--out", "@camp", "--quiet"},
       {"table", "a FIFO"}},
      {"FifoAsBenchConfig", {"bench", "--config", "@fifo", "--listen", "127.0.0.1:0"},
       {"--config", "a FIFO"}},
      {"FifoAsBenchTokenFile", {"bench", "--token-file", "@fifo", "--listen", "127.0.0.1:0"},
       {"--token-file", "a FIFO"}},
      {"FifoAsBenchRealTimeConfig",
       {"bench", "--real-time", "@fifo", "--listen", "127.0.0.1:0"},
       {"--real-time", "a FIFO"}},
      {"FifoAsMonitorTokenFile",
       {"run", "@numerical.yaml", "--out", "@o.csv", "--monitor", "127.0.0.1:0",
        "--token-file", "@fifo"},
       {"--token-file", "a FIFO"}},
      {"FifoAsCompareInput", {"compare", "@fifo", "@garbage.csv"}, {"run_a", "a FIFO"}},
      {"FifoAsReportInput", {"report", "@fifo"}, {"run", "a FIFO"}},
      {"FifoAsPlotInput", {"plot", "@fifo"}, {"run", "a FIFO"}},
      {"FifoAsExportInput", {"export", "@fifo", "--csv", "@x.csv"}, {"run", "a FIFO"}},
      {"FifoAsMonitorInput", {"monitor", "@fifo", "--listen", "127.0.0.1:0"}, {"run", "a FIFO"}},
      {"FifoAsResumeInput", {"resume", "@fifo"}, {"run", "a FIFO"}},
      // Input that was silently accepted or refused with the wrong status (issue 33 item 9).
      {"ProgressQuietMaybe", {"run", "@quiet.yaml", "--out", "@o.csv"},
       {"progress.quiet = 'maybe'", "true or false"}},
      {"SafetyOnANumericalSlot", {"run", "@safety_numerical.yaml", "--out", "@o.csv"},
       {"substructures.r1.safety", "type: physical"}},
      {"MeasuredStiffnessOnANumericalSlot", {"run", "@k0_numerical.yaml", "--out", "@o.csv"},
       {"substructures.r1.initial_stiffness", "remove it"}},
      {"UnknownTopLevelKeyOfABenchFile",
       {"bench", "--config", "@bench_unknown.yaml", "--listen", "127.0.0.1:0"},
       {"unknown key 'safety'", "bench, openfresco"}},
      {"UnknownTopLevelKeyOfABenchFileOfARun",
       {"run", "@emulated_unknown.yaml", "--out", "@o.csv"},
       {"unknown key 'safety'"}},
      {"MonitorLingerNan",
       {"run", "@numerical.yaml", "--out", "@o.csv", "--monitor", "127.0.0.1:0",
        "--monitor-linger", "nan"},
       {"--monitor-linger", "nan"}},
      {"MonitorIntervalNan", {"monitor", "@garbage.csv", "--interval", "nan"},
       {"--interval", "finite number"}},
      {"BenchForAnEmulatedSlot", {"run", "@emulated.yaml", "--out", "@o.csv", "--bench",
                                  "127.0.0.1:1"},
       {"--bench 127.0.0.1:1", "remove --bench"}},
      {"BenchWithoutAPhysicalSlot",
       {"run", "@numerical.yaml", "--out", "@o.csv", "--bench", "127.0.0.1:1"},
       {"--bench", "no physical slot"}},
      {"TokenFileWithoutMonitor",
       {"run", "@numerical.yaml", "--out", "@o.csv", "--token-file", "@token"},
       {"--token-file", "add --monitor"}},
      {"MissingRunForResume", {"resume", "@missing.csv"}, {"missing.csv", "no such file"}},
      {"MissingRunForMonitor", {"monitor", "@missing.csv"}, {"missing.csv", "no such file"}},
      {"MissingRunForCompare", {"compare", "@missing.csv", "@missing.csv"}, {"no such file"}},
      {"MissingRunForReport", {"report", "@missing.csv"}, {"missing.csv", "no such file"}},
      {"MissingRunForPlot", {"plot", "@missing.csv"}, {"missing.csv", "no such file"}},
      {"GarbageRunForResume", {"resume", "@garbage.csv"}, {"run", "not a run journal"}},
      {"GarbageRunForMonitor", {"monitor", "@garbage.csv", "--listen", "127.0.0.1:0"},
       {"run", "not a run journal"}},
      {"GarbageRunForCompare", {"compare", "@garbage.csv", "@garbage.csv"},
       {"run_a", "not a readable run"}},
      {"GarbageRunForReport", {"report", "@garbage.csv"}, {"run", "not a readable run"}},
      {"GarbageRunForPlot", {"plot", "@garbage.csv"}, {"run", "not a readable run"}},
      {"UserTableauWithoutA", {"run", "@tableau.yaml", "--out", "@o.csv"},
       {"integrator.tableau.a", "missing"}},
      // Numbers that size a loop or an allocation (issue 33 item 8).
      {"PlantRateOf1e12Hz", {"run", "@rate.yaml", "--out", "@o.csv", "--clock", "virtual"},
       {"substructures.r1.transfer.rate_hz", "from 1 to 1e+06"}},
      {"CompensatorWindowOf1e12s", {"run", "@window.yaml", "--out", "@o.csv"},
       {"substructures.r1.transfer.window", "to 10"}},
      {"CampaignGridOf1e9Cases", {"campaign", "@campaign_1e9.yaml", "--out", "@camp", "--quiet"},
       {"grid.model.parameters.blade1.k_b", "at most 100000"}},
      {"CampaignGridOf1e7Cases", {"campaign", "@campaign_1e7.yaml", "--out", "@camp", "--quiet"},
       {"10000 × 1000", "at most 100000"}},
      {"ListOf100001Values", {"run", "@list.yaml", "--out", "@o.csv"},
       {"test.serials", "at most 100000"}},
  };
  return cases;
}

class InputRefusal : public ::testing::TestWithParam<Case> {};

TEST_P(InputRefusal, ExitsTwoWithinFiveSecondsNamingTheKey) {
  const Case& c = GetParam();
  std::vector<std::string> argv{kExe};
  for (const std::string& a : c.args) argv.push_back(a.rfind('@', 0) == 0 ? In(a.substr(1)) : a);
  const fs::path output = Dir() / (c.name + ".out");
  const auto start = std::chrono::steady_clock::now();
  Child child(argv, output);
  const int status = child.WaitExit(5.0);  // the contract's bound; -2: still running
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  RecordProperty("seconds", std::to_string(seconds));
  const std::string out = child.output();
  ASSERT_NE(status, -2) << c.name << " still running after 5 s; output so far:\n" << out;
  EXPECT_EQ(status, 2) << out;
  for (const std::string& e : c.expected) EXPECT_THAT(out, HasSubstr(e));
  // Nothing was written where a run would have gone.
  EXPECT_FALSE(fs::exists(Dir() / "o.csv")) << out;
}

INSTANTIATE_TEST_SUITE_P(Issue33, InputRefusal, ::testing::ValuesIn(Cases()),
                         [](const ::testing::TestParamInfo<Case>& param) {
                           return param.param.name;
                         });

}  // namespace
}  // namespace hybridtest
