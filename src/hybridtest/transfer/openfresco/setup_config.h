#pragma once
// The `openfresco:` section of a bench file: the ExpSetup (setup.h) `hybridtest bench --protocol
// openfresco` serves with. It sits at the top level of the bench file, beside `bench:` (or,
// equally, inside `bench:`; not both):
//
//   openfresco:
//     units: {length: mm, force: N}     # units of the numbers on the wire: mm|m, N|kN
//     transform: [[0.6, -0.8, -0.6, 0.8]]   # T (1 × n): command offset from p0 = T d
//     initial_stiffness: 7200           # optional K0 [N/m]; default: the specimen law's
//                                       # initial stiffness (bench.specimen)
//
// p0 is the bench's own (bench.p0_mm).
#include <string>
#include <string_view>

#include <yaml-cpp/yaml.h>

#include "hybridtest/transfer/bench_config.h"
#include "hybridtest/transfer/openfresco/setup.h"

namespace hybridtest::transfer::openfresco {

// Parses the `openfresco:` mapping itself; `where` is its key path for messages ("b.yaml:
// openfresco"). p0 and the default K0 come from `bench`. Throws ConfigError naming the key.
ExpSetup ParseSetup(const YAML::Node& node, std::string_view where,
                    const EmulatedBenchConfig& bench);

// Reads the `openfresco:` section of the bench file at `path`. Throws ConfigError if the file
// has none (naming the example to copy), has two, or the section is invalid.
ExpSetup LoadSetup(const std::string& path, const EmulatedBenchConfig& bench);

}  // namespace hybridtest::transfer::openfresco
