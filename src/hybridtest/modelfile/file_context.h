#pragma once
// Internal to the model-file reader: what the element readers share while one file is built
// (the YAML, the names declared so far, the builder) and the readers themselves.
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "hybridtest/common/yaml_input.h"
#include "hybridtest/modelfile/expression.h"
#include "hybridtest/modelfile/kinematics_mirror.h"
#include "hybridtest/multibody/model.h"

namespace hybridtest::modelfile::internal {

// Dimensions where expressions are used.
inline constexpr Dim kLength{true, {1, 0, 0}};
inline constexpr Dim kMass{true, {0, 1, 0}};
inline constexpr Dim kInertia{true, {2, 1, 0}};
inline constexpr Dim kForce{true, {1, 1, -2}};
inline constexpr Dim kMoment{true, {2, 1, -2}};
inline constexpr Dim kDimensionless{true, {0, 0, 0}};

struct FileContext {
  const YamlInput& in;
  SymbolTable symbols;
  std::map<std::string, multibody::FrameId> frames;
  std::map<std::string, multibody::PointId> points;
  multibody::ModelBuilder* builder = nullptr;
  int num_coordinates = 0;
  // Slot names, known before the slots are read, so that a slot used outside a load is named
  // as such instead of "unknown name".
  std::vector<std::string> slot_names;
  // Where the first kinematic expression that is not affine was written (the engine then needs
  // jets, capped at kMaxJetCoordinates coordinates): named when the cap is hit.
  mutable std::string first_general;
  // The frames and points as read, for velocity() in loads (kinematics_mirror.h).
  std::shared_ptr<Mirror> mirror = std::make_shared<Mirror>();
  // If set, every `csv:` table read is appended here (its path), for the run's record.
  std::vector<std::string>* tables_read = nullptr;

  // "file:line: key_path".
  std::string Where(const YAML::Node& node, const std::string& key_path) const {
    return in.Where(node, key_path);
  }
  // parent[key], which must be present: otherwise a ConfigError at the parent's line,
  // "file:line: kp.key: missing; expected <expected>; add `key: ...` to kp".
  YAML::Node Require(const YAML::Node& parent, const std::string& key, const std::string& kp,
                     const std::string& expected) const;
  // The elements of a 3-vector `node` at `kp` ([x, y, z]); refused with `expected` otherwise,
  // with a hint when a formula with a comma was not quoted (`pow(L, 2)` splits in YAML).
  void RequireVector3(const YAML::Node& node, const std::string& kp,
                      const std::string& expected) const;
  // The expression written at `node` (a number or a formula). Throws ConfigError naming the
  // place, the token and the fix; also when `want` is known and the expression's dimension is
  // known and another (expression.h, Dim).
  Expression Parse(const YAML::Node& node, const std::string& key_path, Dim want = {}) const;
  // As Parse, for expressions of t and the coordinates only (angles, positions,
  // displacements, W(q)).
  Expression ParseKinematic(const YAML::Node& node, const std::string& key_path,
                            Dim want = {}) const;
  // Throws ConfigError if `want` and e's dimension are known and differ.
  void CheckDim(const YAML::Node& node, const std::string& key_path, const Expression& e,
                const Dim& want) const;
  // A value that must be constant (masses, inertias, stiffnesses): numbers and parameters.
  double Constant(const YAML::Node& node, const std::string& key_path,
                  const std::string& expected, Dim want = {}) const;
  // A kinematic expression as the engine's ScalarField (affine when it can be).
  multibody::ScalarField Field(const YAML::Node& node, const std::string& key_path,
                               Dim want = {}) const;
  multibody::FrameId Frame(const YAML::Node& node, const std::string& key_path) const;
  multibody::PointId Point(const YAML::Node& node, const std::string& key_path) const;
};

// Readers of the sections, in the order they are built (model_file_elements.cc,
// model_file_loads.cc).
void ReadKinematicalEquations(FileContext& c, const YAML::Node& node);
void ReadFrames(FileContext& c, const YAML::Node& node);
void ReadPoints(FileContext& c, const YAML::Node& node);
void ReadMasses(FileContext& c, const YAML::Node& particles, const YAML::Node& bodies);
void ReadTables(FileContext& c, const YAML::Node& node);
void ReadTimeFunctions(FileContext& c, const YAML::Node& node);
// Slots: declares them in the builder; returns each slot's default stiffness.
std::vector<double> ReadSlots(FileContext& c, const YAML::Node& node);
void ReadLoads(FileContext& c, const YAML::Node& forces, const YAML::Node& torques);
// `states:` (names already declared, in order): the rates and initial values, into the builder.
void ReadExtraStates(FileContext& c, const YAML::Node& node);

// `constraints:` and their options (model_file_constraints.cc): into the builder; returns the
// constraint items (for their lines).
std::vector<YAML::Node> ReadConstraints(FileContext& c, const YAML::Node& root);
// Refuses (ConfigError at the constraint's or dependent_speeds' line) constraints that cannot
// be met at the model's initial state, or a singular choice of dependent speeds there.
void CheckConstraintsAtInitialState(const FileContext& c, const YAML::Node& root,
                                    const std::vector<YAML::Node>& items,
                                    const multibody::Model& model);

// The elements of the optional list section `node` at `key` (empty when absent), with
// `repeat:` blocks expanded:
//   - repeat: {i: [1, 2, 3]}
//     items:
//       - {name: B$i, parent: H, axis: z, angle: psi + ($i - 1) * 2 * pi / 3 + beta$i}
// copies `items` once per value, replacing $i (or ${i}) in every scalar by the value as written.
// `labels` (if given) receives each element's key path: "frames[2]" or, for an expanded one,
// "frames[1].items[0] (i = 2)".
std::vector<YAML::Node> ListItems(const YamlInput& in, const YAML::Node& node,
                                  const std::string& key,
                                  std::vector<std::string>* labels = nullptr);

}  // namespace hybridtest::modelfile::internal
