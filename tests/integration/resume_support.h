#pragma once
// Support for the resume tests (run_resume_test.cc, run_resume_stops_test.cc): runs killed at
// a chosen point, resumed, and journals compared line by line and field by field.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "integration/child_process.h"
#include "support/temp_dir.h"

namespace hybridtest::testing {

namespace fs = std::filesystem;

inline const std::string kSource = HYBRIDTEST_SOURCE_DIR;

// The sidecar (.meta.json) of the journal `csv`.
inline nlohmann::json Sidecar(const fs::path& csv) {
  std::ifstream in(fs::path(csv).replace_extension(".meta.json"));
  return nlohmann::json::parse(in);
}

// In the tests' scratch directory (support/temp_dir.h: /dev/shm when there is one): these tests
// are about resuming, not about the disk, and a physical run syncs every row (a tmpfs makes
// fsync free and the suite fast).
inline fs::path ResumeTestDir(const std::string& name) {
  const fs::path dir =
      test_support::ScratchBase() / fmt::format("hybridtest_resume_{}_{}", name, ::getpid());
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

inline std::vector<std::string> ReadLines(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  std::string line;
  while (std::getline(in, line)) lines.push_back(line);
  return lines;
}

inline std::vector<std::string> SplitCsv(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream in(line);
  std::string field;
  while (std::getline(in, field, ',')) fields.push_back(field);
  return fields;
}

// The argv of `hybridtest <args>` (HYBRIDTEST_BINARY first).
inline std::vector<std::string> HybridtestArgv(const std::vector<std::string>& args) {
  std::vector<std::string> argv{HYBRIDTEST_BINARY};
  argv.insert(argv.end(), args.begin(), args.end());
  return argv;
}

// `run <config> --out <csv> --quiet`, with `--bench <bench>` when a bench address is given.
inline std::vector<std::string> RunArgs(const std::string& config, const fs::path& csv,
                                        const std::string& bench = "") {
  std::vector<std::string> args{"run", config, "--out", csv.string(), "--quiet"};
  if (!bench.empty()) args.insert(args.end(), {"--bench", bench});
  return args;
}

// Runs `hybridtest <args>` to completion (≤ 120 s); returns its exit status.
inline int RunToEnd(const std::vector<std::string>& args, const fs::path& log) {
  Child child(HybridtestArgv(args), log);
  const int status = child.WaitExit(120.0);
  EXPECT_EQ(status, 0) << child.output();
  return status;
}

// Starts `hybridtest <args>` writing `csv` and sends `signal` once the journal holds at least
// `bytes` bytes (polled). Returns true if the signal arrived before the run ended by itself
// (exited, or completed its journal and sidecar and was exiting).
inline bool RunAndSignalAt(const std::vector<std::string>& args, const fs::path& csv,
                           std::uintmax_t bytes, int signal, const fs::path& log,
                           int expected_status) {
  Child child(HybridtestArgv(args), log);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  for (;;) {
    std::error_code error;
    const auto size = fs::file_size(csv, error);
    if (!error && size >= bytes) break;
    if (std::chrono::steady_clock::now() > deadline) break;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  child.Signal(signal);
  const int status = child.WaitExit(60.0);
  if (status == 0) return false;  // finished before the signal
  // The journal's size on disk lags the run (buffered rows): the signal can land after the run
  // completed, while the process exits. Its sidecar then says so, and nothing was interrupted.
  std::ifstream sidecar(fs::path(csv).replace_extension(".meta.json"));
  const auto meta = nlohmann::json::parse(sidecar, nullptr, /*allow_exceptions=*/false);
  if (meta.is_object() && meta.value("status", "") == "completed") return false;
  EXPECT_EQ(status, expected_status) << child.output();
  return true;
}

// `hybridtest resume csv <extra>`; returns its exit status and output.
inline std::pair<int, std::string> Resume(const fs::path& csv,
                                          const std::vector<std::string>& extra,
                                          const fs::path& log) {
  std::vector<std::string> args{"resume", csv.string()};
  args.insert(args.end(), extra.begin(), extra.end());
  Child child(HybridtestArgv(args), log);
  const int status = child.WaitExit(120.0);
  return {status, child.output()};
}

// Every line equal, except the fields of columns named "*_lab_time" if skip_lab_time (the
// bench's clock also counts the re-imposition on resume).
inline void ExpectSameJournal(const std::vector<std::string>& reference,
                              const std::vector<std::string>& resumed, bool skip_lab_time) {
  ASSERT_EQ(resumed.size(), reference.size());
  ASSERT_FALSE(reference.empty());
  const auto header = SplitCsv(reference[0]);
  for (std::size_t i = 0; i < reference.size(); ++i) {
    if (!skip_lab_time) {
      ASSERT_EQ(resumed[i], reference[i]) << "line " << i;
      continue;
    }
    const auto a = SplitCsv(reference[i]);
    const auto b = SplitCsv(resumed[i]);
    ASSERT_EQ(a.size(), b.size()) << "line " << i;
    for (std::size_t c = 0; c < a.size(); ++c) {
      if (header[c].ends_with("_lab_time")) continue;
      ASSERT_EQ(b[c], a[c]) << "line " << i << ", column " << header[c];
    }
  }
}

// A seeded generator whose seed is printed, so a failing trial can be replayed.
inline std::mt19937_64 TrialGenerator() {
  const auto seed = std::random_device{}();
  std::cout << "[ resume trials: seed " << seed << " ]\n";
  return std::mt19937_64(seed);
}

}  // namespace hybridtest::testing
