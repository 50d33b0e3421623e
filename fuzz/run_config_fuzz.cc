// libFuzzer target: the run-config loader (io/config.h, io/substructure_config.h), fed as
// YAML text. Every input must load or raise a hybridtest::Error (which the CLI maps to its
// exit codes); a crash, a hang, a sanitizer report or any other exception (which the CLI would
// report as an internal error, exit 70) is a finding.
#include <cstddef>
#include <cstdint>
#include <string>

#include "hybridtest/common/error.h"
#include "hybridtest/io/config.h"
#include "hybridtest/io/substructure_config.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const hybridtest::io::SimulationConfig cfg = hybridtest::io::ParseSimulationConfig(
        hybridtest::YamlInput::FromText(text, "fuzz.yaml"));
    // Remote transfers are built but never connect (Activate is not called).
    (void)hybridtest::io::MakeSubstructures(cfg, {});
  } catch (const hybridtest::Error&) {
  }
  return 0;
}
