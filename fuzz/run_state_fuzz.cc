// libFuzzer target: the run state reader (runner/run_state.h), fed as JSON text, and its check
// against a journal. Every input must be accepted or refused with a hybridtest::Error (the CLI
// maps ConfigError to exit 2); a crash, a sanitizer report or any other exception is a
// finding. Each input is tried twice: as given (almost always refused by its checksum) and
// with its checksum made right, so that the fields behind the checksum are fuzzed too.
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <string>

#include "hybridtest/common/error.h"
#include "hybridtest/runner/run_state.h"

namespace {

// A small journal to check states against (written once per process).
const std::string& JournalPath() {
  static const std::string path = [] {
    const std::string p = "/tmp/hybridtest_fuzz_run_state_" + std::to_string(::getpid()) + ".csv";
    std::ofstream(p) << "t,q1,u1,r1\n0,0,0,0\n0.001,1e-06,0.002,-0.0072\n0.002,4e-06,0.004,nan\n";
    return p;
  }();
  return path;
}

void Try(const nlohmann::json& j) {
  try {
    const hybridtest::runner::RunState state = hybridtest::runner::RunStateFromJson(j, "fuzz.json");
    hybridtest::runner::VerifyRunStateAgainstJournal(state, JournalPath());
  } catch (const hybridtest::Error&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(data, data + size);
  } catch (const nlohmann::json::exception&) {
    return 0;  // LoadRunState reports this as ConfigError itself
  }
  Try(j);
  if (j.is_object()) {
    j["checksum"] = hybridtest::runner::RunStateChecksum(j);
    Try(j);
  }
  return 0;
}
