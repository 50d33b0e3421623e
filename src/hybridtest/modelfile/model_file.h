#pragma once
// A model file: a multibody model written in YAML instead of C++ (docs/model-files.md has the
// full format and a complete example). A run config uses it with `model: {file: PATH}`.
//
//   name: pendulum
//   parameters:
//     m: {value: 1.0, unit: kg, description: bob mass}
//     l: {value: 0.8, unit: m, description: rod length}
//     g: {value: 9.81, unit: m/s², description: gravity}
//   coordinates:
//     - {name: theta, unit: rad, description: rod angle from the vertical}
//   frames:
//     - {name: A, parent: N, axis: z, angle: theta}
//   points:
//     - {name: P, from: O, frame: A, position: [l, 0, 0]}
//   particles:
//     - {name: bob, point: P, mass: m}
//   forces:
//     - {name: gravity, point: P, expressed_in: N, value: [m * g, 0, 0]}
//
// Reading is in two steps, so that a run config can override parameters in between:
// LoadModelFile parses the YAML and the declared parameters; BuildModelFile parses every
// expression (parameters become constants), builds the multibody Model and returns it with
// the resolved parameters. Every error is a ConfigError naming file:line, the key path, the
// offending token and the fix.
#include <string>
#include <vector>

#include "hybridtest/common/yaml_input.h"
#include "hybridtest/models/catalogue.h"

namespace hybridtest::modelfile {

struct ModelFile {
  YamlInput input;                  // the parsed file (path, text, tree)
  std::string name;                 // `name:`, default: the file's stem
  std::string description;          // `description:`, default: "model file PATH"
  models::ParameterSet parameters;  // as declared in the file (SI)
};

// Reads and checks the top level and the parameters of the model file at `path`.
ModelFile LoadModelFile(const std::string& path);
ModelFile ParseModelFile(YamlInput input);

// Builds the model with `parameters` (the file's, possibly overridden). If `tables_read` is
// given, the path of every `csv:` table the build reads is appended to it (a run records
// every file it read). Throws ConfigError.
models::BuiltModel BuildModelFile(const ModelFile& file, const models::ParameterSet& parameters,
                                  std::vector<std::string>* tables_read = nullptr);

}  // namespace hybridtest::modelfile
