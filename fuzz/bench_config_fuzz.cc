// libFuzzer target: the emulated bench's config loader (transfer/bench_spec.h: a bench of one
// actuator or of `actuators: n`), fed as YAML text with a top-level `bench:` mapping. Every
// input must load (and then build an EmulatedBench) or raise a hybridtest::Error; anything else
// is a finding.
#include <cstddef>
#include <cstdint>
#include <string>

#include "hybridtest/common/error.h"
#include "hybridtest/common/yaml_input.h"
#include "hybridtest/transfer/bench_spec.h"
#include "hybridtest/transfer/emulated_bench.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const hybridtest::YamlInput in = hybridtest::YamlInput::FromText(text, "fuzz.yaml");
    // Both forms of a bench file (one actuator, or `actuators: n`), read as the run reads them.
    const hybridtest::transfer::EmulatedBenchSpec spec =
        hybridtest::transfer::ParseEmulatedBenchSpec(in.root()["bench"], "fuzz.yaml: bench");
    (void)hybridtest::transfer::MakeEmulatedBench(spec);
  } catch (const hybridtest::Error&) {
  }
  return 0;
}
