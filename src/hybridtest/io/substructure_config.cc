// See substructure_config.h.
#include "hybridtest/io/substructure_config.h"
#include "hybridtest/io/physical_slot_config.h"
#include "hybridtest/io/setup_config.h"

#include <Eigen/Core>

#include <algorithm>
#include <fmt/core.h>

#include <filesystem>

#include "hybridtest/common/error.h"
#include "hybridtest/constitutive/linear_spring.h"
#include "hybridtest/constitutive/parse_law.h"
#include "hybridtest/constitutive/parse_vector_law.h"
#include "hybridtest/fmi/fmu_config.h"
#include "hybridtest/substructures/numerical_substructure.h"
#include "hybridtest/substructures/physical_substructure.h"

namespace hybridtest::io {
namespace {

using substructures::Substructure;
using internal::ParseInitialStiffness;
using internal::ParseSafety;
using internal::ParseSetup;
using internal::ParseTransfer;
using internal::TakesBenchAddress;

// A key that only a physical substructure reads, given on a numerical one, is refused: it
// would be ignored, and a user who wrote `safety:` believes a limit guards the slot.
void RefusePhysicalKeys(const YamlInput& in, const YAML::Node& node, const std::string& kp,
                        std::initializer_list<const char*> keys) {
  for (const char* key : keys) {
    if (!node[key]) continue;
    throw ConfigError(fmt::format(
        "{}: a numerical substructure has no {}; `{}:` only applies to `type: physical`: remove "
        "it, or make the slot physical", in.Where(node[key], kp + "." + key),
        std::string_view(key) == "safety"              ? "safety limits"
        : std::string_view(key) == "initial_stiffness" ? "measured initial stiffness (its law "
                                                         "gives the stiffness)"
        : std::string_view(key) == "transfer"          ? "transfer system"
                                                       : "actuator setup",
        key));
  }
}

substructures::SubstructureSpec DefaultNumerical(const SimulationConfig& cfg, int slot) {
  const double k = cfg.model.slot_stiffness.at(slot);
  return substructures::NumericalSpec(cfg.model.model.slots()[slot].info.name,
                                      std::make_unique<constitutive::LinearSpring>(k, "model default"));
}

// A substructure of several slots (`slots: [rA, rB]`): numerical with a stiffness matrix, or
// physical with a linear setup (`setup: {p0: [..], transform: [[..]]}`) on n actuators.
substructures::SubstructureSpec ParseBlock(const YamlInput& in, const YAML::Node& node,
                                           const std::string& name, const std::string& kp,
                                           const SubstructureOptions& options) {
  substructures::SubstructureSpec spec;
  spec.slot = name;
  for (const auto& s : node["slots"]) spec.slots.push_back(in.String(s, kp + ".slots", "a slot name"));
  const std::string type = in.String(node["type"], kp + ".type", "numerical or physical");
  const auto m = static_cast<Eigen::Index>(spec.slots.size());
  if (type == "numerical") {
    RefusePhysicalKeys(in, node, kp, {"transfer", "safety", "initial_stiffness"});
    const YAML::Node law = node["law"];
    const char* expected = "{type: linear, stiffness: [[k11, k12], [k21, k22]]} in N/m, one row "
                           "per slot, or a coupled law ({type: bouc_wen_biaxial, ...}) with an "
                           "optional `transform:` (n_axes × m)";
    if (!law || !law.IsMap() || !law["type"]) {
      throw ConfigError(fmt::format("{}: a numerical substructure of several slots needs `law: "
                                    "{}`", in.Where(node, kp + ".law"), expected));
    }
    if (law["type"].as<std::string>() == "linear" && !node["transform"] && !node["setup"]) {
      if (!law["stiffness"]) in.ThrowValue(law, kp + ".law", expected);
      spec.stiffness = ReadMatrix(in, law["stiffness"], kp + ".law.stiffness", expected);
      if (spec.stiffness->rows() != m || spec.stiffness->cols() != m) {
        in.ThrowValue(law["stiffness"], kp + ".law.stiffness", expected);
      }
      return spec;
    }
    // A coupled law of n axes seen through a large-displacement setup: r = J(d)ᵀ F(ℓ(d) − L0).
    if (IsLargeDisplacementSetup(in, node["setup"], kp + ".setup")) {
      spec.block_setup = ParseRodSetup(in, node["setup"], kp + ".setup", static_cast<int>(m));
      spec.block_law = constitutive::ParseVectorLaw(law, spec.block_setup->num_actuators(),
                                                    kp + ".law");
      return spec;
    }
    if (node["setup"]) {
      in.ThrowValue(node["setup"], kp + ".setup",
                    "`{geometry: large_displacement, ...}` (a numerical block gives a linear map "
                    "as `transform:` beside `law:`)");
    }
    // A coupled law of n axes seen through T (n × m): r = Tᵀ F(T d) (law_block.h).
    Eigen::MatrixXd t = Eigen::MatrixXd::Identity(m, m);
    if (node["transform"]) {
      t = ReadMatrix(in, node["transform"], kp + ".transform",
                     "a list of rows, one per axis of the law, one column per slot");
      if (t.cols() != m) in.ThrowValue(node["transform"], kp + ".transform", "one column per slot");
    }
    spec.block_law = constitutive::ParseVectorLaw(law, static_cast<int>(t.rows()), kp + ".law");
    spec.block_transform = t;
    return spec;
  }
  if (type != "physical") {
    throw ConfigError(fmt::format("{} = '{}': expected numerical or physical",
                                  in.Where(node["type"], kp + ".type"), type));
  }
  if (!options.allow_physical) {
    throw ConfigError(fmt::format("{}: substructure {} is physical; {}", in.Where(node, kp), name,
                                  options.physical_hint));
  }
  const YAML::Node setup = node["setup"];
  const std::string sp = kp + ".setup";
  substructures::PhysicalSpec physical;
  Eigen::Index n = 0;
  if (IsLargeDisplacementSetup(in, setup, sp)) {
    physical.actuator_setup = ParseRodSetup(in, setup, sp, static_cast<int>(m));
    n = physical.actuator_setup->num_actuators();
  } else {
    physical.linear = ParseLinearSetup(in, setup, sp, static_cast<int>(m));
    n = physical.linear->num_actuators();
  }
  for (Eigen::Index k = 0; k < n; ++k) {
    physical.actuator_limits.push_back(ParseSafety(
        in, PickActuator(in, WithoutSlotLimits(node["safety"]), static_cast<std::size_t>(k),
                         static_cast<std::size_t>(n), kp + ".safety"),
        fmt::format("{}.safety (actuator {})", kp, k + 1)));
  }
  physical.limits = physical.actuator_limits[0];
  for (const auto& l : physical.actuator_limits) {  // the transfer waits for the slowest
    physical.limits.timeout = std::max(physical.limits.timeout, l.timeout);
  }
  const YAML::Node tr = in.Mapping(node, "transfer", kp + ".transfer", true);
  physical.slot_limits = ParseSlotLimits(in, node["safety"], kp + ".safety", spec.slots);
  if (physical.actuator_setup) {
    CheckGeometryWithinStroke(in, setup, sp,
                              static_cast<const substructures::RodSetup&>(*physical.actuator_setup),
                              physical.actuator_limits, physical.slot_limits);
  }
  physical.transfer = ParseTransfer(in, tr, kp + ".transfer", options, physical.limits.timeout,
                                    nullptr);
  if (const YAML::Node k0 = node["initial_stiffness"]) {
    if (k0.IsSequence()) {
      physical.initial_stiffness_matrix =
          ReadMatrix(in, k0, kp + ".initial_stiffness", "an m × m matrix in N/m");
    } else {
      ParseInitialStiffness(in, k0, kp, physical);
      if (physical.initial_stiffness) {
        in.ThrowValue(k0, kp + ".initial_stiffness",
                      "an m × m matrix in N/m, `measure`, or {measure: true, amplitude: 0.001}");
      }
    }
  }
  spec.physical = std::move(physical);
  return spec;
}

// A `type: fmu` substructure; its FMU file is one of the run's inputs.
substructures::SubstructureSpec ParseFmu(const YamlInput& in, const YAML::Node& node,
                                         const std::string& name,
                                         const std::vector<std::string>& slots,
                                         const std::string& kp, const SubstructureOptions& options) {
  std::string file;
  auto spec = fmi::ParseFmuSubstructure(in, node, name, slots, kp, &file);
  if (options.files_read != nullptr) options.files_read->push_back({"fmu", file});
  return spec;
}

}  // namespace

std::vector<substructures::SubstructureSpec> ParseSubstructureSpecs(
    const SimulationConfig& cfg, const SubstructureOptions& options) {
  const YamlInput& in = cfg.input;
  const auto& slots = cfg.model.model.slots();
  std::vector<substructures::SubstructureSpec> result(slots.size());
  std::vector<bool> given(slots.size(), false);
  std::vector<substructures::SubstructureSpec> blocks;  // substructures with `slots:`
  const YAML::Node section = in.Mapping(in.root(), "substructures", "substructures", false);
  if (section.IsDefined()) {
    for (const auto& kv : section) {
      const std::string slot_name = in.String(kv.first, "substructures", "a slot name");
      const std::string kp = "substructures." + slot_name;
      if (kv.second.IsMap() && kv.second["slots"]) {
        if (fmi::IsFmuNode(kv.second)) {  // an FMU of several slots (fmi/fmu_config.h)
          std::vector<std::string> names;
          for (const auto& s : kv.second["slots"]) names.push_back(in.String(s, kp + ".slots", "a slot name"));
          blocks.push_back(ParseFmu(in, kv.second, slot_name, names, kp, options));
        } else {
          in.CheckKeys(kv.second, kp, {"type", "slots", "law", "transform", "transfer", "setup",
                                       "safety", "initial_stiffness"});
          blocks.push_back(ParseBlock(in, kv.second, slot_name, kp, options));
        }
        for (const auto& name : blocks.back().slots) {
          bool known = false;
          for (std::size_t s = 0; s < slots.size(); ++s) {
            if (slots[s].info.name != name) continue;
            known = true;
            if (given[s]) {
              throw ConfigError(fmt::format("{}: slot {} is given twice; give each slot to one "
                                            "substructure", in.Where(kv.second["slots"],
                                                                     kp + ".slots"), name));
            }
            given[s] = true;
          }
          if (!known) {
            throw ConfigError(fmt::format("{}: the {} model has no slot '{}'",
                                          in.Where(kv.second["slots"], kp + ".slots"),
                                          cfg.model.name, name));
          }
        }
        continue;
      }
      int slot = -1;
      for (std::size_t s = 0; s < slots.size(); ++s) {
        if (slots[s].info.name == slot_name) slot = static_cast<int>(s);
      }
      if (slot < 0) {
        std::string known;
        for (const auto& s : slots) known += (known.empty() ? "" : ", ") + s.info.name;
        throw ConfigError(fmt::format("{}: the {} model has no restoring-force slot '{}'; its "
                                      "slots are: {}", in.Where(kv.first, kp), cfg.model.name,
                                      slot_name, known.empty() ? "(none)" : known));
      }
      const YAML::Node node = kv.second;
      if (!node.IsMap()) {
        throw ConfigError(fmt::format("{}: expected a mapping with `type: numerical` or "
                                      "`type: physical`", in.Where(node, kp)));
      }
      if (fmi::IsFmuNode(node)) {  // one slot served by an FMU (fmi/fmu_config.h)
        if (given[slot]) {
          throw ConfigError(fmt::format("{}: slot {} is given twice; give each slot to one "
                                        "substructure", in.Where(node, kp), slot_name));
        }
        given[slot] = true;
        result[slot] = ParseFmu(in, node, slot_name, {slot_name}, kp, options);
        continue;
      }
      in.CheckKeys(node, kp, {"type", "law", "transfer", "setup", "safety", "initial_stiffness"});
      const std::string type = in.String(node["type"], kp + ".type", "numerical or physical");
      if (given[slot]) {
        throw ConfigError(fmt::format("{}: slot {} is given twice; give each slot to one "
                                      "substructure", in.Where(node, kp), slot_name));
      }
      given[slot] = true;
      if (type == "numerical") {
        RefusePhysicalKeys(in, node, kp, {"transfer", "setup", "safety", "initial_stiffness"});
        result[slot] = node["law"] ? substructures::NumericalSpec(
                                         slot_name, constitutive::ParseRestoringForceLaw(
                                                        node["law"], in.Where(node["law"], kp + ".law")))
                                   : DefaultNumerical(cfg, slot);
      } else if (type == "physical") {
        if (!options.allow_physical) {
          throw ConfigError(fmt::format("{}: slot {} is physical; {}", in.Where(node, kp),
                                        slot_name, options.physical_hint));
        }
        const YAML::Node tr = in.Mapping(node, "transfer", kp + ".transfer", true);
        const transfer::SafetyLimits limits = ParseSafety(in, node["safety"], kp + ".safety");
        substructures::PhysicalSpec physical;
        physical.transfer = ParseTransfer(in, tr, kp + ".transfer", options, limits.timeout,
                                          node["safety"].IsMap() ? &limits : nullptr);
        physical.setup = ParseSetup(in, node["setup"], kp + ".setup");
        physical.limits = limits;
        if (node["safety"].IsMap() && node["safety"]["initial_stiffness"]) {
          physical.safety_stiffness = in.PositiveNumber(node["safety"]["initial_stiffness"],
                                                        kp + ".safety.initial_stiffness",
                                                        "the specimen's expected stiffness in N/m");
        }
        if (node["initial_stiffness"]) {
          ParseInitialStiffness(in, node["initial_stiffness"], kp, physical);
        }
        result[slot].slot = slot_name;
        result[slot].physical = std::move(physical);
      } else {
        throw ConfigError(fmt::format("{} = '{}': expected numerical or physical",
                                      in.Where(node["type"], kp + ".type"), type));
      }
    }
  }
  for (std::size_t s = 0; s < slots.size(); ++s) {
    if (!given[s]) result[s] = DefaultNumerical(cfg, static_cast<int>(s));
  }
  // --bench HOST:PORT names the server of a networked slot: given for a config that has none,
  // it would be ignored and the test would run against something else than the user thinks.
  if (options.bench_address && !options.bench_address->empty() && !options.emulate_bench) {
    bool taken = false;
    if (section.IsDefined()) {
      for (const auto& kv : section) {
        const YAML::Node node = kv.second;
        taken = taken || (node.IsMap() && node["type"] && node["type"].IsScalar() &&
                          node["type"].Scalar() == "physical" && TakesBenchAddress(node["transfer"]));
      }
    }
    if (!taken) {
      throw ConfigError(fmt::format(
          "--bench {}: {} has no physical slot with a networked transfer system (remote, "
          "modbus or openfresco); every physical slot is emulated or there is none: remove "
          "--bench, or give a slot `transfer: {{type: remote}}`", *options.bench_address,
          in.path().empty() ? std::string("the run config") : in.path()));
    }
  }
  if (blocks.empty()) return result;
  // The one-slot substructures in slot order, then the blocks in config order.
  std::vector<substructures::SubstructureSpec> mixed;
  for (auto& spec : result) {
    if (!spec.slot.empty()) mixed.push_back(std::move(spec));
  }
  for (auto& b : blocks) mixed.push_back(std::move(b));
  return mixed;
}

std::vector<std::unique_ptr<Substructure>> MakeSubstructures(const SimulationConfig& cfg,
                                                             const SubstructureOptions& options) {
  std::vector<std::unique_ptr<Substructure>> built;
  for (const auto& spec : ParseSubstructureSpecs(cfg, options)) built.push_back(spec.Build());
  return built;
}

}  // namespace hybridtest::io
