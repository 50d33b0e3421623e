// See model_description.h.
#include "hybridtest/fmi/model_description.h"

#include <fmt/core.h>
#include <pugixml.hpp>

#include <algorithm>
#include <cstdlib>
#include <sstream>

#include "hybridtest/common/error.h"

namespace hybridtest::fmi {
namespace {

bool Flag(const pugi::xml_node& node, const char* fmi2_name, const char* fmi3_name) {
  return node.attribute(fmi2_name).as_bool(false) || node.attribute(fmi3_name).as_bool(false);
}

UnitDefinition ReadUnit(const pugi::xml_node& unit) {
  UnitDefinition u;
  u.name = unit.attribute("name").as_string();
  const pugi::xml_node base = unit.child("BaseUnit");
  if (base) {
    u.has_base_unit = true;
    u.kg = base.attribute("kg").as_int(0);
    u.m = base.attribute("m").as_int(0);
    u.s = base.attribute("s").as_int(0);
    u.a = base.attribute("A").as_int(0);
    u.k = base.attribute("K").as_int(0);
    u.mol = base.attribute("mol").as_int(0);
    u.cd = base.attribute("cd").as_int(0);
    u.rad = base.attribute("rad").as_int(0);
    u.factor = base.attribute("factor").as_double(1.0);
    u.offset = base.attribute("offset").as_double(0.0);
  }
  return u;
}

// FMI 2 nests the type (<ScalarVariable><Real unit=../></ScalarVariable>); FMI 3 names it
// (<Float64 unit=../>). `declared_units`: the unit of each declaredType.
ModelVariable ReadVariable(const pugi::xml_node& node, bool fmi3, int index,
                           const std::map<std::string, std::string>& declared_units) {
  ModelVariable v;
  v.index = index;
  v.name = node.attribute("name").as_string();
  v.value_reference = node.attribute("valueReference").as_uint(0);
  if (const auto c = node.attribute("causality")) v.causality = c.as_string();
  if (const auto c = node.attribute("variability")) v.variability = c.as_string();
  pugi::xml_node typed = fmi3 ? node : node.first_child();
  while (!fmi3 && typed && typed.type() != pugi::node_element) typed = typed.next_sibling();
  if (!typed) return v;
  v.type = typed.name();
  v.unit = typed.attribute("unit").as_string();
  if (v.unit.empty()) {
    const auto it = declared_units.find(typed.attribute("declaredType").as_string());
    if (it != declared_units.end()) v.unit = it->second;
  }
  if (const auto s = typed.attribute("start")) v.start = s.as_string();
  if (fmi3) {
    for (const auto& d : node.children("Dimension")) {
      v.dimensions.push_back(d.attribute("start")
                                 ? std::string(d.attribute("start").as_string())
                                 : "valueReference " +
                                       std::string(d.attribute("valueReference").as_string()));
    }
  }
  if (!fmi3 && v.type != "Real" && v.variability == "continuous" && !node.attribute("variability")) {
    v.variability = "discrete";  // FMI 2: only Real variables may be continuous
  }
  return v;
}

// The 1-based line of byte `offset` of `text` (0 when pugixml gives no offset).
int LineAt(const std::string& text, std::ptrdiff_t offset) {
  if (offset < 0) return 0;
  const auto end = text.begin() + std::min<std::ptrdiff_t>(offset, std::ssize(text));
  return 1 + static_cast<int>(std::count(text.begin(), end, '\n'));
}

std::vector<int> ParseIndices(const std::string& text) {
  std::vector<int> out;
  std::istringstream in(text);
  long long value = 0;
  while (in >> value) out.push_back(static_cast<int>(value));
  return out;
}

}  // namespace

std::string ModelVariable::DimensionsText() const {
  std::string text;
  for (const auto& d : dimensions) text += "[" + d + "]";
  return text;
}

const ModelVariable* ModelDescription::Find(const std::string& name) const {
  for (const auto& v : variables) {
    if (v.name == name) return &v;
  }
  return nullptr;
}

const UnitDefinition* ModelDescription::UnitOf(const ModelVariable& v) const {
  if (v.unit.empty()) return nullptr;
  const auto it = units.find(v.unit);
  return it == units.end() ? nullptr : &it->second;
}

bool ModelDescription::DeclaresNoState() const {
  if (num_states > 0) return false;
  for (const auto& v : variables) {
    if (v.variability == "discrete" && (v.causality == "local" || v.causality == "output")) {
      return false;
    }
  }
  for (const auto& [output, deps] : output_dependencies) {
    if (!deps) return false;
    for (int d : *deps) {
      if (d < 1 || d > static_cast<int>(variables.size()) ||
          variables[static_cast<std::size_t>(d - 1)].causality != "input") {
        return false;
      }
    }
  }
  return true;
}

ModelDescription ParseModelDescription(const std::string& xml, const std::string& where) {
  pugi::xml_document doc;
  const pugi::xml_parse_result parsed = doc.load_buffer(xml.data(), xml.size());
  if (!parsed) {
    throw ConfigError(fmt::format("{}: modelDescription.xml is not well-formed XML ({} at byte "
                                  "{})", where, parsed.description(), parsed.offset));
  }
  const pugi::xml_node root = doc.child("fmiModelDescription");
  if (!root) {
    throw ConfigError(fmt::format("{}: modelDescription.xml has no fmiModelDescription root "
                                  "element; is this an FMU?", where));
  }
  ModelDescription md;
  md.fmi_version = root.attribute("fmiVersion").as_string();
  const bool fmi3 = md.is_fmi3();
  if (md.fmi_version != "2.0" && !fmi3) {
    throw ConfigError(fmt::format("{}: fmiVersion '{}'; hybridtest imports FMI 2.0 and 3.0 "
                                  "FMUs: export the model as FMI 2.0 or 3.0", where,
                                  md.fmi_version));
  }
  md.model_name = root.attribute("modelName").as_string();
  md.guid = root.attribute(fmi3 ? "instantiationToken" : "guid").as_string();
  if (const pugi::xml_node cs = root.child("CoSimulation")) {
    md.model_identifier = cs.attribute("modelIdentifier").as_string();
    md.can_get_and_set_state = Flag(cs, "canGetAndSetFMUstate", "canGetAndSetFMUState");
    md.can_serialize_state = Flag(cs, "canSerializeFMUstate", "canSerializeFMUState");
    md.can_handle_variable_step = cs.attribute("canHandleVariableCommunicationStepSize").as_bool(false);
    md.needs_execution_tool = cs.attribute("needsExecutionTool").as_bool(false);
  }
  for (const auto& unit : root.child("UnitDefinitions").children("Unit")) {
    UnitDefinition u = ReadUnit(unit);
    md.units[u.name] = u;
  }
  std::map<std::string, std::string> declared_units;
  for (const auto& type : root.child("TypeDefinitions").children()) {
    // FMI 2: <SimpleType name=..><Real unit=../></SimpleType>; FMI 3: <Float64Type name=.. unit=..>
    const pugi::xml_node typed = fmi3 ? type : type.first_child();
    if (typed && typed.attribute("unit")) {
      declared_units[type.attribute("name").as_string()] = typed.attribute("unit").as_string();
    }
  }
  // Each variable once: a config names variables, and a second one of the same name would be
  // silently shadowed by the first (FMI 2.0 section 2.2.7, FMI 3.0 section 2.4.7: names are
  // unique).
  int index = 0;
  std::map<std::string, int> lines;  // name → line of its first declaration
  for (const auto& node : root.child("ModelVariables").children()) {
    if (node.type() != pugi::node_element) continue;
    md.variables.push_back(ReadVariable(node, fmi3, ++index, declared_units));
    const int line = LineAt(xml, node.offset_debug());
    const auto [first, inserted] = lines.emplace(md.variables.back().name, line);
    if (!inserted) {
      throw ConfigError(fmt::format(
          "{}: modelDescription.xml:{}: variable '{}' is declared twice (lines {} and {}); "
          "variable names of an FMU are unique (FMI 2.0 section 2.2.7, FMI 3.0 section 2.4.7): "
          "re-export the FMU with one variable of each name", where, line,
          md.variables.back().name, first->second, line));
    }
  }
  // FMI 3 names dependencies by value reference: turned into indices here.
  auto index_of_reference = [&](int vr) {
    for (const auto& v : md.variables) {
      if (static_cast<int>(v.value_reference) == vr) return v.index;
    }
    return 0;
  };
  const pugi::xml_node structure = root.child("ModelStructure");
  const auto read_output = [&](const pugi::xml_node& out, int output_index) {
    std::optional<std::vector<int>> deps;
    if (const auto d = out.attribute("dependencies")) {
      deps = ParseIndices(d.as_string());
      if (fmi3) {
        for (int& i : *deps) i = index_of_reference(i);
      }
    }
    md.output_dependencies[output_index] = deps;
  };
  if (fmi3) {
    for (const auto& out : structure.children("Output")) {
      read_output(out, index_of_reference(out.attribute("valueReference").as_int(-1)));
    }
    for (const auto& s : structure.children()) {
      const std::string name = s.name();
      if (name == "ContinuousStateDerivative" || name == "ClockedState") ++md.num_states;
    }
  } else {
    for (const auto& out : structure.child("Outputs").children("Unknown")) {
      read_output(out, out.attribute("index").as_int(0));
    }
    for (const auto& d : structure.child("Derivatives").children("Unknown")) {
      (void)d;
      ++md.num_states;
    }
  }
  return md;
}

}  // namespace hybridtest::fmi
