// See fmu_config.h.
#include "hybridtest/fmi/fmu_config.h"

#include <fmt/core.h>

#include <algorithm>
#include <filesystem>
#include <memory>

#include "hybridtest/common/error.h"
#include "hybridtest/fmi/fmu_archive.h"
#include "hybridtest/fmi/fmu_substructure.h"
#include "hybridtest/fmi/fmu_units.h"

namespace hybridtest::fmi {
namespace {

std::vector<std::string> Names(const YamlInput& in, const YAML::Node& node, const std::string& kp,
                               std::size_t m, const char* what) {
  std::vector<std::string> names;
  if (node && node.IsScalar()) {
    names.push_back(node.Scalar());
  } else if (node && node.IsSequence()) {
    for (const auto& n : node) names.push_back(in.String(n, kp, what));
  }
  if (names.size() != m) {
    in.ThrowValue(node, kp, fmt::format("{} {} (one per slot, in slot order)", m == 1 ? "the" : std::to_string(m) + " names of the", what));
  }
  return names;
}

std::string Known(const ModelDescription& md, const char* causality) {
  std::string out;
  for (const auto& v : md.variables) {
    if (v.causality == causality) out += (out.empty() ? "" : ", ") + v.name;
  }
  return out.empty() ? "(none)" : out;
}

std::optional<Eigen::MatrixXd> ReadStiffness(const YamlInput& in, const YAML::Node& node,
                                             const std::string& kp, std::size_t m) {
  if (!node) return std::nullopt;
  const auto n = static_cast<Eigen::Index>(m);
  Eigen::MatrixXd k(n, n);
  const char* expected = "K0 in N/m: a number for one slot, an m × m list of rows for m slots";
  if (node.IsScalar() && m == 1) {
    k(0, 0) = in.Number(node, kp, expected);
    return k;
  }
  if (!node.IsSequence() || node.size() != m) in.ThrowValue(node, kp, expected);
  for (std::size_t i = 0; i < m; ++i) {
    const auto row = in.Numbers(node[i], kp, expected);
    if (row.size() != m) in.ThrowValue(node, kp, expected);
    for (std::size_t j = 0; j < m; ++j) {
      k(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = row[j];
    }
  }
  return k;
}

}  // namespace

namespace {

// FMI 3 arrays are refused at config time, naming the variable and its dimensions (issue 48).
void RequireScalar(const YamlInput& in, const YAML::Node& node, const std::string& kp,
                   const std::string& fmu, const ModelVariable& v) {
  if (v.dimensions.empty()) return;
  throw ConfigError(fmt::format(
      "{}: {}: variable '{}' is an array {} (FMI 3 <Dimension>); hybridtest binds scalar "
      "variables only, one per slot or parameter: give the FMU one scalar variable per value "
      "(or wrap it in an FMU that does)", in.Where(node, kp), fmu, v.name, v.DimensionsText()));
}

}  // namespace

const ModelVariable& Require(const YamlInput& in, const YAML::Node& node, const std::string& kp,
                             const std::string& fmu, const ModelDescription& md,
                             const std::string& name, const char* causality, const char* role) {
  const ModelVariable* v = md.Find(name);
  if (v == nullptr) {
    throw ConfigError(fmt::format("{}: {}: the FMU has no variable '{}'; its {}s are: {}",
                                  in.Where(node, kp), fmu, name, causality,
                                  Known(md, causality)));
  }
  if (v->causality != causality) {
    throw ConfigError(fmt::format("{}: {}: variable '{}' has causality {}; {} must be an {} "
                                  "of the FMU (its {}s are: {})", in.Where(node, kp), fmu, name,
                                  v->causality, role, causality, causality, Known(md, causality)));
  }
  const char* real = md.is_fmi3() ? "Float64" : "Real";
  if (v->type != real) {
    throw ConfigError(fmt::format("{}: {}: variable '{}' is of type {}; {} must be a {}",
                                  in.Where(node, kp), fmu, name, v->type, role, real));
  }
  RequireScalar(in, node, kp, fmu, *v);
  return *v;
}

std::vector<FmuInstance::Value> ReadParameters(const YamlInput& in, const YAML::Node& node,
                                                const std::string& kp, const std::string& fmu,
                                                const ModelDescription& md) {
  std::vector<FmuInstance::Value> out;
  if (!node) return out;
  in.RequireMapping(node, kp);
  for (const auto& kv : node) {
    const std::string name = in.String(kv.first, kp, "a parameter name");
    const std::string key = kp + "." + name;
    const ModelVariable* v = md.Find(name);
    if (v == nullptr || v->causality != "parameter") {
      throw ConfigError(fmt::format(
          "{}: {}: {}; the FMU's parameters are: {}", in.Where(kv.first, key), fmu,
          v == nullptr ? fmt::format("the FMU has no variable '{}'", name)
                       : fmt::format("variable '{}' has causality {}, not parameter", name,
                                     v->causality),
          Known(md, "parameter")));
    }
    if (v->variability != "fixed" && v->variability != "tunable") {
      throw ConfigError(fmt::format("{}: {}: parameter '{}' is {} and cannot be set",
                                    in.Where(kv.second, key), fmu, name, v->variability));
    }
    RequireScalar(in, kv.second, key, fmu, *v);
    double value = 0.0;
    if (v->type == "Boolean" && kv.second.IsScalar() &&
        (kv.second.Scalar() == "true" || kv.second.Scalar() == "false")) {
      value = kv.second.Scalar() == "true" ? 1.0 : 0.0;
    } else if (v->type == "Real" || v->type == "Integer" || v->type == "Enumeration" ||
               v->type == "Float64" || v->type == "Int32") {
      value = in.Number(kv.second, key, fmt::format("a number in the FMU's unit{}",
                                                    v->unit.empty() ? "" : " (" + v->unit + ")"));
    } else {
      throw ConfigError(fmt::format("{}: {}: parameter '{}' is of type {}, which hybridtest "
                                    "cannot set (Real/Float64, Integer/Int32, Enumeration, "
                                    "Boolean)", in.Where(kv.second, key), fmu, name, v->type));
    }
    out.push_back({v, value});
  }
  return out;
}

std::string ReadFmuFile(const YamlInput& in, const YAML::Node& node, const std::string& kp,
                        ModelDescription* md) {
  namespace fs = std::filesystem;
  fs::path file = in.String(node["fmu"], kp + ".fmu", "the FMU file (.fmu), relative to this config");
  if (file.is_relative() && !in.path().empty()) file = fs::path(in.path()).parent_path() / file;
  const std::string fmu = fs::absolute(file).lexically_normal().string();
  if (!fs::is_regular_file(fmu)) {
    throw ConfigError(fmt::format("{}: no FMU file at {}", in.Where(node["fmu"], kp + ".fmu"),
                                  fmu));
  }
  *md = ParseModelDescription(ReadMember(fmu, "modelDescription.xml"), fmu);
  const std::string where = in.Where(node, kp);
  if (md->model_identifier.empty()) {
    throw ConfigError(fmt::format("{}: {}: the FMU does not support co-simulation (no "
                                  "CoSimulation element); export it for co-simulation",
                                  where, fmu));
  }
  const std::string binary =
      fmt::format("binaries/{}/{}.so", PlatformFolder(*md), md->model_identifier);
  const auto members = ListMembers(fmu);
  if (std::find(members.begin(), members.end(), binary) == members.end()) {
    throw ConfigError(fmt::format("{}: {}: no binary for this platform ({} is missing); export "
                                  "a binary FMU for Linux x86-64", where, fmu, binary));
  }
  return fmu;
}

bool IsFmuNode(const YAML::Node& node) {
  return node.IsMap() && node["type"] && node["type"].IsScalar() && node["type"].Scalar() == "fmu";
}

substructures::SubstructureSpec ParseFmuSubstructure(const YamlInput& in, const YAML::Node& node,
                                                     const std::string& name,
                                                     const std::vector<std::string>& slots,
                                                     const std::string& kp,
                                                     std::string* fmu_file) {
  if (node["velocity"]) {
    throw ConfigError(fmt::format(
        "{}: velocity inputs are not passed to an FMU substructure: hybridtest tries a "
        "substructure with its slot displacements only (the one seam, decision 0021; a stage's "
        "velocity is not a trial's input); remove `velocity:` and differentiate the "
        "displacement inside the FMU", in.Where(node["velocity"], kp + ".velocity")));
  }
  in.CheckKeys(node, kp, {"type", "slots", "fmu", "displacement", "force", "parameters",
                          "initial_stiffness"});
  auto b = std::make_shared<FmuBinding>();
  b->name = name;
  b->fmu = ReadFmuFile(in, node, kp, &b->md);
  const ModelDescription& md = b->md;
  const std::string where = in.Where(node, kp);
  // Displacements in, forces out, one each per slot; their units.
  const std::size_t m = slots.size();
  const auto inputs = Names(in, node["displacement"], kp + ".displacement", m, "FMU input");
  const auto outputs = Names(in, node["force"], kp + ".force", m, "FMU output");
  for (std::size_t k = 0; k < m; ++k) {
    const auto& x = Require(in, node["displacement"], kp + ".displacement", b->fmu, md,
                            inputs[k], "input", "a slot displacement");
    const auto& f = Require(in, node["force"], kp + ".force", b->fmu, md, outputs[k], "output",
                            "a restoring force");
    const UnitCheck units = CheckSlotUnits(md, x, f, b->fmu);
    b->inputs.push_back(&x);
    b->outputs.push_back(&f);
    b->in_factor.push_back(units.in_factor);
    b->in_offset.push_back(units.in_offset);
    b->out_factor.push_back(units.out_factor);
    b->out_offset.push_back(units.out_offset);
  }
  // An input left unbound keeps its start value; one that is a velocity would silently stay 0.
  for (const auto& v : md.variables) {
    const UnitDefinition* u = v.causality == "input" ? md.UnitOf(v) : nullptr;
    const bool bound = std::find(b->inputs.begin(), b->inputs.end(), &v) != b->inputs.end();
    if (u != nullptr && u->has_base_unit && !bound && u->s == -1 && u->kg == 0 &&
        ((u->m == 1 && u->rad == 0) || (u->m == 0 && u->rad == 1))) {
      throw ConfigError(fmt::format(
          "{}: {}: the FMU declares input '{}' in {}, a velocity, which hybridtest cannot give "
          "(a substructure is tried with displacements only, decision 0021): export the FMU "
          "with the displacement as its only kinematic input and differentiate it inside",
          where, b->fmu, v.name, v.unit));
    }
  }
  b->parameters = ReadParameters(in, node["parameters"], kp + ".parameters", b->fmu, md);
  b->initial_stiffness = ReadStiffness(in, node["initial_stiffness"], kp + ".initial_stiffness", m);
  // State: rolled back before each trial, or none at all.
  b->stateless = md.DeclaresNoState();
  if (!b->stateless && !md.can_get_and_set_state) {
    throw ConfigError(fmt::format(
        "{}: {}: the FMU keeps a state ({}) but does not declare canGetAndSetFMUstate; "
        "hybridtest tries a substructure at several stages before it commits a step and must "
        "roll the FMU back to its committed state before each trial: export the FMU with "
        "FMU-state support (get/set FMU state), or, if it has no state, declare its outputs' "
        "dependencies on its inputs only", where, b->fmu,
        md.num_states > 0 ? fmt::format("{} continuous state(s)", md.num_states)
                          : "outputs that may depend on more than its inputs, or a discrete "
                            "variable"));
  }
  substructures::SubstructureSpec spec;
  spec.slot = name;
  if (node["slots"]) spec.slots = slots;
  spec.custom = [b] { return std::make_unique<FmuSubstructure>(b); };
  if (fmu_file != nullptr) *fmu_file = b->fmu;
  return spec;
}

}  // namespace hybridtest::fmi
