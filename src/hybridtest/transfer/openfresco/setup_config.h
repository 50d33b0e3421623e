#pragma once
// The `openfresco:` section of a bench file: the ExpSetup (setup.h) `hybridtest bench --protocol
// openfresco` serves with. It sits at the top level of the bench file, beside `bench:` (or,
// equally, inside `bench:`; not both):
//
//   openfresco:
//     units: {length: mm, force: N}     # units of the numbers on the wire: mm|m, N|kN
//     transform: [[0.6, -0.8, -0.6, 0.8]]   # T (1 × n): command offset from p0 = T d
//     initial_stiffness: 7200           # optional K0 [N/m] (or [[7200]]); default: the
//                                       # specimen law's initial stiffness (bench.specimen)
//
// p0 is the bench's own (bench.p0_mm).
//
// A bench of several actuators (`bench: {actuators: n_act, ...}`) takes T with one row per
// actuator (n_act × n) and, optionally, `initial_stiffness` as an n_act × n_act matrix in
// actuator coordinates [N/m] (default: the specimen's virgin stiffness matrix); p0 is each
// actuator's own:
//
//   openfresco:
//     units: {length: mm, force: N}
//     transform: [[1, 0], [0.6, 0.8]]   # T (n_act × n): a − p0 = T d
//     initial_stiffness: [[5000, 1200], [1200, 3000]]   # optional K_a [N/m]
#include <string>
#include <string_view>

#include <yaml-cpp/yaml.h>

#include "hybridtest/transfer/bench_config.h"
#include "hybridtest/transfer/bench_spec.h"
#include "hybridtest/transfer/openfresco/setup.h"

namespace hybridtest::transfer::openfresco {

// Parses the `openfresco:` mapping itself for the n_act actuators of `bench` (one row of T per
// actuator); `where` is its key path for messages ("b.yaml: openfresco"). p0 and the default
// K_a come from `bench`. Throws ConfigError naming the key (a row count other than the bench's
// actuators, rows of unequal length, dependent rows, a stiffness of the wrong size).
ExpSetup ParseSetup(const YAML::Node& node, std::string_view where, const EmulatedBenchSpec& bench);

// Reads the `openfresco:` section of the bench file at `path`. Throws ConfigError if the file
// has none (naming the example to copy), has two, or the section is invalid.
ExpSetup LoadSetup(const std::string& path, const EmulatedBenchSpec& bench);

}  // namespace hybridtest::transfer::openfresco
