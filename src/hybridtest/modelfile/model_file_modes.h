#pragma once
// A model file's optional `modes:` section: how `hybridtest modes` (and Python's
// hybridtest.modes) present the model's modes (docs/model-files.md, "Modes").
//
//   modes:
//     coordinates: [q4, q7]          # the coordinates a reader looks at (default: all
//                                    # independent ones): modes are named by the dominant
//                                    # ones and shapes normalised on the largest of them
//     labels:                        # first match names a mode; modes with λ = 0 get none
//       - {name: weave, oscillatory: true}
//       - {name: capsize, oscillatory: false, dominant: q4}
//
// A label matches a mode whose eigenvalue has the character `oscillatory` (true: Im λ ≠ 0,
// false: real; absent: either) and, when `dominant` is given, whose largest shape entry among
// `coordinates` is that coordinate. Names of coordinates are checked against the model by
// the analysis (io/modes_analysis.h), which knows them; `where` keeps each name's place.
#include <optional>
#include <string>
#include <vector>

#include "hybridtest/modelfile/model_file.h"

namespace hybridtest::modelfile {

struct ModeLabel {
  std::string name;
  std::optional<bool> oscillatory;   // absent: either character
  std::string dominant;              // a coordinate's name, empty: any
  std::string where;                 // "file.yaml:12: modes.labels[0]" for messages
};

struct ModeReading {
  std::vector<std::string> coordinates;   // empty: every independent coordinate
  std::vector<std::string> coordinates_where;
  std::vector<ModeLabel> labels;
};

// Reads and checks `modes:` (absent: an empty reading). Throws ConfigError naming the key for
// an unknown key, a label without a name, a repeated label name or coordinate, or a value of
// the wrong kind.
ModeReading ReadModeReading(const YamlInput& in);

}  // namespace hybridtest::modelfile
