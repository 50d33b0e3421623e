// See export_layout.h.
#include "export_layout.h"

#include <fmt/core.h>

#include <array>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "hybridtest/common/error.h"

namespace hybridtest::fmu_export {
namespace {

// SI base-unit exponents of a hybridtest unit string: kg, m, s, rad.
using Exponents = std::array<int, 4>;

std::optional<Exponents> SymbolExponents(const std::string& symbol) {
  static const std::map<std::string, Exponents> known{
      {"kg", {1, 0, 0, 0}}, {"m", {0, 1, 0, 0}}, {"s", {0, 0, 1, 0}}, {"rad", {0, 0, 0, 1}},
      {"N", {1, 1, -2, 0}}, {"J", {1, 2, -2, 0}}, {"W", {1, 2, -3, 0}}, {"Pa", {1, -1, -2, 0}},
      {"Hz", {0, 0, -1, 0}}, {"1", {0, 0, 0, 0}}};
  const auto it = known.find(symbol);
  if (it == known.end()) return std::nullopt;
  return it->second;
}

// One factor "m²", "s^-1", "kg" times `sign`, added to `e`; false if unknown.
bool AddFactor(std::string factor, int sign, Exponents& e) {
  int power = 1;
  for (const auto& [suffix, p] : std::vector<std::pair<std::string, int>>{{"²", 2}, {"³", 3}}) {
    if (factor.size() > suffix.size() && factor.ends_with(suffix)) {
      factor.resize(factor.size() - suffix.size());
      power = p;
    }
  }
  if (const auto caret = factor.find('^'); caret != std::string::npos) {
    try {
      power = std::stoi(factor.substr(caret + 1));
    } catch (const std::exception&) {
      return false;
    }
    factor.resize(caret);
  }
  const auto base = SymbolExponents(factor);
  if (!base) return false;
  for (std::size_t i = 0; i < e.size(); ++i) e[i] += sign * power * (*base)[i];
  return true;
}

// "N·m·s", "kg·m²", "1/s", "N/m": the exponents, or nullopt for a unit not parsed here.
std::optional<Exponents> UnitExponents(const std::string& unit) {
  Exponents e{0, 0, 0, 0};
  int sign = 1;
  std::string factor;
  auto flush = [&]() {
    if (factor.empty()) return true;
    const bool ok = AddFactor(factor, sign, e);
    factor.clear();
    return ok;
  };
  for (std::size_t i = 0; i < unit.size(); ++i) {
    if (unit.compare(i, 2, "·") == 0 || unit[i] == '*' || unit[i] == '.' || unit[i] == ' ') {
      if (!flush()) return std::nullopt;
      if (unit.compare(i, 2, "·") == 0) ++i;
    } else if (unit[i] == '/') {
      if (!flush() || sign < 0) return std::nullopt;
      sign = -1;
    } else {
      factor += unit[i];
    }
  }
  if (!flush()) return std::nullopt;
  return e;
}

std::string Escape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string Number(double v) { return fmt::format("{:.17g}", v); }

}  // namespace

Layout MakeLayout(const io::RunSpec& spec, std::vector<ExportedBlock> blocks) {
  const multibody::Model& model = spec.model.model;
  Layout layout;
  layout.blocks = std::move(blocks);
  std::map<std::string, int> slot_index;
  for (int i = 0; i < model.num_slots(); ++i) slot_index[model.slots()[i].info.name] = i;
  // Per-instance parameters ("blade1.f_w") of an all-instances one ("f_w"): the model gives an
  // instance the config does not set the all-instances value. The FMU declares one kind per
  // name so that each parameter has one meaning (issue 48): the all-instances one while every
  // instance has its value, else the per-instance ones (the config gave them their own).
  const auto& parameters = spec.model.parameters;
  std::map<std::string, bool> uniform;  // all-instances name -> every instance has its value
  const auto base_of = [&](const std::string& name) {
    const auto dot = name.find('.');
    return dot != std::string::npos && parameters.Has(name.substr(dot + 1)) ? name.substr(dot + 1)
                                                                          : std::string();
  };
  for (const auto& p : parameters.all()) {
    const std::string base = base_of(p.name);
    if (base.empty()) continue;
    const bool same = p.value == parameters.Get(base);
    const auto [it, added] = uniform.emplace(base, same);
    if (!added) it->second = it->second && same;
  }
  int index = 0;
  for (const auto& p : parameters.all()) {
    const int i = index++;  // into parameters.all(), declared or not
    const std::string base = base_of(p.name);
    const bool hidden = base.empty() ? uniform.contains(p.name) && !uniform.at(p.name)
                                     : uniform.at(base);
    if (hidden) continue;
    layout.variables.push_back({Variable::Kind::kParameter, p.name, p.unit, p.description,
                                p.value, i});
  }
  std::vector<int> exported;
  for (const auto& block : layout.blocks) {
    for (const auto& slot : block.slots) {
      if (!slot_index.contains(slot)) {
        throw ConfigError(fmt::format("export-fmu: the model has no slot '{}'", slot));
      }
      layout.slots.push_back(slot);
      exported.push_back(slot_index[slot]);
    }
  }
  for (std::size_t k = 0; k < exported.size(); ++k) {
    const auto& info = model.slots()[exported[k]].info;
    layout.variables.push_back({Variable::Kind::kInput, info.name, info.unit,
                                "restoring force of slot " + info.name + " (" + info.description +
                                    "), from the co-simulation master",
                                0.0, static_cast<int>(k)});
  }
  for (std::size_t k = 0; k < exported.size(); ++k) {
    const auto& info = model.slots()[exported[k]].info;
    const std::string unit = info.unit == "N·m" ? "rad" : "m";
    layout.variables.push_back({Variable::Kind::kDisplacement, "d_" + info.name, unit,
                                "displacement of slot " + info.name, 0.0, static_cast<int>(k)});
  }
  const int n = model.num_coordinates();
  for (int i = 0; i < n; ++i) {
    const auto& q = model.coordinates()[i];
    layout.variables.push_back({Variable::Kind::kCoordinate, q.name, q.unit, q.description,
                                spec.x0(i), i});
  }
  for (int i = 0; i < n; ++i) {
    const auto& u = model.speeds()[i];
    layout.variables.push_back({Variable::Kind::kSpeed, u.name, u.unit, u.description,
                                spec.x0(n + i), i});
  }
  std::set<std::string> names;
  for (const auto& v : layout.variables) {
    if (!names.insert(v.name).second) {
      throw ConfigError(fmt::format("export-fmu: two variables would be named '{}' (a "
                                    "parameter, slot or coordinate of the model); rename one in "
                                    "the model file", v.name));
    }
  }
  return layout;
}

nlohmann::json BlocksToJson(const std::vector<ExportedBlock>& blocks) {
  nlohmann::json j = nlohmann::json::array();
  for (const auto& b : blocks) j.push_back({{"slots", b.slots}, {"k0", b.k0}});
  return j;
}

std::vector<ExportedBlock> BlocksFromJson(const nlohmann::json& j) {
  std::vector<ExportedBlock> blocks;
  for (const auto& b : j) {
    blocks.push_back({b.at("slots").get<std::vector<std::string>>(),
                      b.at("k0").get<std::vector<std::vector<double>>>()});
  }
  return blocks;
}

const char* Causality(const Variable& v) {
  switch (v.kind) {
    case Variable::Kind::kParameter: return "parameter";
    case Variable::Kind::kInput: return "input";
    default: return "output";
  }
}

std::string VariableTableCsv(const Layout& layout) {
  std::string csv = "name,value_reference,causality,unit,start,description\n";
  const auto quoted = [](const std::string& text) {
    std::string q = "\"";
    for (char c : text) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
  };
  for (std::size_t vr = 0; vr < layout.variables.size(); ++vr) {
    const Variable& v = layout.variables[vr];
    csv += fmt::format("{},{},{},{},{},{}\n", quoted(v.name), vr, Causality(v), quoted(v.unit),
                       Number(v.start), quoted(v.description));
  }
  return csv;
}

std::string ModelDescriptionXml(const Layout& layout, const DescriptionInfo& info) {
  const bool v3 = info.fmi_version == 3;
  std::ostringstream x;
  x << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    << "<!-- Written by hybridtest export-fmu (docs/fmi.md). -->\n"
    << "<fmiModelDescription fmiVersion=\"" << (v3 ? "3.0" : "2.0") << "\" modelName=\""
    << Escape(info.model_name) << "\" " << (v3 ? "instantiationToken" : "guid") << "=\""
    << Escape(info.guid) << "\"\n    description=\"" << Escape(info.description)
    << "\" generationTool=\"hybridtest export-fmu\""
    << (v3 ? "" : " variableNamingConvention=\"flat\" numberOfEventIndicators=\"0\"") << ">\n";
  x << "  <CoSimulation modelIdentifier=\"" << Escape(info.model_identifier)
    << "\" canHandleVariableCommunicationStepSize=\"true\"\n      "
    << (v3 ? "canGetAndSetFMUState=\"true\" canSerializeFMUState=\"true\""
           : "canGetAndSetFMUstate=\"true\" canSerializeFMUstate=\"true\"")
    << (v3 ? " fixedInternalStepSize=\"" + Number(info.step) + "\"" : std::string())
    << "/>\n";
  std::set<std::string> units;
  for (const auto& v : layout.variables) {
    if (!v.unit.empty()) units.insert(v.unit);
  }
  x << "  <UnitDefinitions>\n";
  for (const auto& unit : units) {
    x << "    <Unit name=\"" << Escape(unit) << "\">";
    if (const auto e = UnitExponents(unit)) {
      x << "<BaseUnit";
      const char* names[] = {"kg", "m", "s", "rad"};
      for (int i = 0; i < 4; ++i) {
        if ((*e)[i] != 0) x << ' ' << names[i] << "=\"" << (*e)[i] << '"';
      }
      x << "/>";
    }
    x << "</Unit>\n";
  }
  x << "  </UnitDefinitions>\n";
  x << "  <DefaultExperiment startTime=\"0\" stepSize=\"" << Number(info.step) << "\"/>\n";
  x << "  <ModelVariables>\n";
  for (std::size_t vr = 0; vr < layout.variables.size(); ++vr) {
    const Variable& v = layout.variables[vr];
    const bool parameter = v.kind == Variable::Kind::kParameter;
    const bool input = v.kind == Variable::Kind::kInput;
    const std::string causality = Causality(v);
    const std::string variability = parameter ? "fixed" : "continuous";
    const std::string unit = v.unit.empty() ? "" : " unit=\"" + Escape(v.unit) + "\"";
    // An output's start is given only where FMI allows it (initial="exact").
    const std::string start = " start=\"" + Number(v.start) + "\"";
    const std::string initial = (parameter || input) ? "" : " initial=\"exact\"";
    if (v3) {
      x << "    <Float64 name=\"" << Escape(v.name) << "\" valueReference=\"" << vr
        << "\" causality=\"" << causality << "\" variability=\"" << variability << "\""
        << initial << unit << start << "\n        description=\"" << Escape(v.description)
        << "\"/>\n";
    } else {
      x << "    <ScalarVariable name=\"" << Escape(v.name) << "\" valueReference=\"" << vr
        << "\" causality=\"" << causality << "\" variability=\"" << variability << "\""
        << initial << "\n        description=\"" << Escape(v.description) << "\"><Real"
        << unit << start << "/></ScalarVariable>\n";
    }
  }
  x << "  </ModelVariables>\n  <ModelStructure>\n";
  // Outputs depend on the state only (no direct feedthrough of the inputs): empty dependencies.
  if (!v3) x << "    <Outputs>\n";
  for (std::size_t vr = 0; vr < layout.variables.size(); ++vr) {
    const Variable::Kind k = layout.variables[vr].kind;
    if (k == Variable::Kind::kParameter || k == Variable::Kind::kInput) continue;
    if (v3) {
      x << "    <Output valueReference=\"" << vr << "\" dependencies=\"\"/>\n";
    } else {
      x << "      <Unknown index=\"" << vr + 1 << "\" dependencies=\"\"/>\n";
    }
  }
  if (!v3) x << "    </Outputs>\n";
  x << "  </ModelStructure>\n</fmiModelDescription>\n";
  return x.str();
}

}  // namespace hybridtest::fmu_export
