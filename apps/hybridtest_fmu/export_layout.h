#pragma once
// What an FMU exported by `hybridtest export-fmu` declares (docs/fmi.md, "Exporting"), made
// from a run config the same way by the exporter (which writes modelDescription.xml) and by
// the FMU's binary (which reads the config back from its resources): one layout, so the value
// references cannot disagree.
//
//   value references, in this order:
//     parameters   the model's parameters (their names, e.g. "k_b", "blade1.psi"; SI unit;
//                  start = the value in the config), causality parameter, variability fixed;
//                  of an all-instances parameter ("f_w") and its per-instance ones
//                  ("blade1.f_w"), only the all-instances one while the config gives every
//                  instance its value, else only the per-instance ones: one meaning each
//     inputs       the restoring force of each exported slot (the slots the config's
//                  `substructures:` section names), named after the slot ("r1") [N or N·m]
//     outputs      each exported slot's displacement "d_<slot>" [m or rad], then the model's
//                  coordinates q ("q1", ...) and speeds u ("u1", ...), SI
//
// resources/hybridtest/ holds the config (config.yaml, reduced to the model, its initial
// state and its integrator) with the files it reads (the model file and its tables, at the
// same relative paths), and export.json: the exported slots, in blocks as the config groups
// them, with each block's K0 (m × m) [N/m] and the FMU's communication step (= dt).
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "hybridtest/io/run_spec.h"

namespace hybridtest::fmu_export {

struct Variable {
  enum class Kind { kParameter, kInput, kDisplacement, kCoordinate, kSpeed } kind;
  std::string name;
  std::string unit;         // hybridtest's unit ("N/m", "kg·m²"), "" when dimensionless
  std::string description;
  double start = 0.0;
  int index = 0;            // into the parameters, the exported slots, q or u
};

// One group of exported slots served by one substructure in the config, and its K0.
struct ExportedBlock {
  std::vector<std::string> slots;
  std::vector<std::vector<double>> k0;  // (m × m) [N/m]
};

struct Layout {
  std::vector<Variable> variables;      // value reference = position
  std::vector<ExportedBlock> blocks;
  std::vector<std::string> slots;       // every exported slot, blocks in order
};

// The layout of the model in `spec` (compiled from the reduced config) with `blocks` exported.
// Throws ConfigError if a slot is unknown or two variables would share a name.
Layout MakeLayout(const io::RunSpec& spec, std::vector<ExportedBlock> blocks);

nlohmann::json BlocksToJson(const std::vector<ExportedBlock>& blocks);
std::vector<ExportedBlock> BlocksFromJson(const nlohmann::json& j);

struct DescriptionInfo {
  int fmi_version = 2;          // 2 or 3
  std::string model_name;       // modelName: export-fmu writes the identifier
  std::string model_identifier; // the binary's name (binaries/<platform>/<id>.so)
  std::string guid;             // FMI 2 guid / FMI 3 instantiationToken
  std::string description;
  double step = 0.0;            // the scheme's dt: the FMU's communication step [s]
};

// "parameter", "input" or "output": the variable's causality in the description.
const char* Causality(const Variable& v);
// The variable table a C master needs (export-fmu writes it beside the FMU as
// <name>.variables.csv): one row per variable, in value-reference order, with the columns
// name, value_reference, causality, unit (the description's unit name; "" dimensionless),
// start and description (text fields quoted).
std::string VariableTableCsv(const Layout& layout);

// modelDescription.xml for the layout: every variable named with its unit (UnitDefinitions
// give each unit's SI base-unit exponents), co-simulation with get/set and serialized state.
std::string ModelDescriptionXml(const Layout& layout, const DescriptionInfo& info);

}  // namespace hybridtest::fmu_export
