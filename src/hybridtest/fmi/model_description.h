#pragma once
// What hybridtest reads of an FMU's modelDescription.xml (FMI 2.0, chapter 2.2 and 4.3; FMI
// 3.0, chapter 2.4 and 4.3), parsed with Debian's pugixml: the identity, the co-simulation
// capabilities, the variables (by name: a config never gives a value reference), the unit
// definitions and whether the model declares a state.
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace hybridtest::fmi {

// A unit definition (<Unit name=..><BaseUnit kg=.. m=.. s=.. factor=.. offset=../></Unit>):
// value in SI base units = factor * value + offset.
struct UnitDefinition {
  std::string name;
  bool has_base_unit = false;  // false: only a name is declared (no dimension to check)
  // Exponents of kg, m, s, A, K, mol, cd and rad.
  int kg = 0, m = 0, s = 0, a = 0, k = 0, mol = 0, cd = 0, rad = 0;
  double factor = 1.0;
  double offset = 0.0;
};

struct ModelVariable {
  std::string name;
  unsigned value_reference = 0;
  std::string causality = "local";         // parameter, calculatedParameter, input, output, local, independent, structuralParameter
  std::string variability = "continuous";  // constant, fixed, tunable, discrete, continuous
  std::string type;                        // Real, Integer, Boolean, String, Enumeration (FMI 2); Float64, Int32, ... (FMI 3)
  std::string unit;                        // empty: none declared (own or through declaredType)
  std::optional<std::string> start;
  int index = 0;                           // 1-based position in ModelVariables
  // FMI 3 arrays: one entry per <Dimension>, its size ("3") or, for a size a structural
  // parameter gives, "valueReference 7". Empty: a scalar.
  std::vector<std::string> dimensions;
  // "[3]", "[2][valueReference 7]": the dimensions as FMI 3 writes an array's size.
  std::string DimensionsText() const;
};

struct ModelDescription {
  std::string fmi_version;       // "2.0", "3.0"
  std::string model_name;
  std::string guid;              // FMI 2 guid, FMI 3 instantiationToken
  std::string model_identifier;  // of the CoSimulation element; empty: no co-simulation
  bool can_get_and_set_state = false;
  bool can_serialize_state = false;
  bool can_handle_variable_step = false;
  bool needs_execution_tool = false;
  std::vector<ModelVariable> variables;
  std::map<std::string, UnitDefinition> units;
  // Continuous states: the ModelStructure's Derivatives (FMI 2) or ContinuousStateDerivative
  // entries (FMI 3); FMI 3 also lists clocked states.
  int num_states = 0;
  // Outputs (by variable index): the indices they depend on, or nullopt if not declared
  // (then they may depend on anything).
  std::map<int, std::optional<std::vector<int>>> output_dependencies;

  bool is_fmi3() const { return fmi_version.rfind("3.", 0) == 0; }
  // The variable called `name`, or nullptr.
  const ModelVariable* Find(const std::string& name) const;
  // The unit of `v` (nullptr if it declares none or its unit has no definition).
  const UnitDefinition* UnitOf(const ModelVariable& v) const;
  // Whether the model declares no state: no continuous (or clocked) states, no discrete
  // variable, and every output declares dependencies on inputs only. Such an FMU needs no
  // roll-back between trials.
  bool DeclaresNoState() const;
};

// Parses `xml`; `where` names it in errors (the FMU file). Throws ConfigError for XML that is
// not an FMI 2.0 or 3.0 model description, with the reason, and for a variable name declared
// twice (naming it and both lines of modelDescription.xml).
ModelDescription ParseModelDescription(const std::string& xml, const std::string& where);

}  // namespace hybridtest::fmi
