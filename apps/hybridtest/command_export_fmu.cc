// hybridtest export-fmu CONFIG --out MODEL.fmu [--fmi-version 2|3]: the run config's model as
// a co-simulation FMU (docs/fmi.md, "Exporting"; apps/hybridtest_fmu/). The slots the
// config's `substructures:` section names become the FMU's inputs (their restoring forces,
// from the co-simulation master) and outputs (their displacements), with q and u as outputs and
// the model's parameters as parameters; DoStep advances the configured scheme. The FMU holds
// the binary hybridtest_fmu.so (built beside this program, or installed in
// <prefix>/<libdir>/hybridtest/) and, in resources/hybridtest/, the config reduced to the
// model, its initial state and its integrator, with the files it reads.
#include <fmt/core.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>

#include "cli_values.h"
#include "command.h"
#include "export_layout.h"
#include "hybridtest/common/error.h"
#include "hybridtest/common/module_path.h"
#include "hybridtest/fmi/fmu_archive.h"
#include "hybridtest/io/atomic_file.h"
#include "hybridtest/io/config.h"
#include "hybridtest/io/digest.h"
#include "hybridtest/io/output_guard.h"
#include "hybridtest/io/run_spec_yaml.h"

namespace hybridtest::app {
namespace {

namespace fs = std::filesystem;
using fmu_export::ExportedBlock;

struct ExportFmuOptions {
  std::string config;
  std::string out;
  int fmi_version = 2;
};

std::string Slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError("cannot read " + path.string());
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The FMU binary: $HYBRIDTEST_FMU_BINARY, else beside this program (a build tree), else in
// the installed library folder (FindModule, common/module_path.h).
fs::path FmuBinary() {
  const ModuleLookup lookup = FindModule("hybridtest_fmu.so", "HYBRIDTEST_FMU_BINARY");
  if (lookup.found) return lookup.found->lexically_normal();
  throw ConfigError(fmt::format(
      "export-fmu: the FMU binary hybridtest_fmu.so is in none of {}: build it "
      "(cmake --build --preset release --target hybridtest_fmu, or scripts/build.sh --app) or "
      "name it with HYBRIDTEST_FMU_BINARY", lookup.searched));
}

// The slots the config's `substructures:` section names (keys, or a block's `slots:`).
std::set<std::string> ConfiguredSlots(const YAML::Node& root) {
  std::set<std::string> slots;
  const YAML::Node section = root["substructures"];
  if (!section || !section.IsMap()) return slots;
  for (const auto& entry : section) {
    const YAML::Node node = entry.second;
    if (node.IsMap() && node["slots"] && node["slots"].IsSequence()) {
      for (const auto& s : node["slots"]) slots.insert(s.as<std::string>());
    } else {
      slots.insert(entry.first.as<std::string>());
    }
  }
  return slots;
}

// The exported blocks with their K0, as the compiled spec's substructures give it.
std::vector<ExportedBlock> ExportedBlocks(const io::RunSpec& spec, const std::set<std::string>& configured) {
  std::vector<ExportedBlock> blocks;
  for (const auto& s : spec.substructures) {
    const auto names = s.SlotNames();
    if (!configured.contains(names.at(0))) continue;
    std::optional<Eigen::MatrixXd> k0;
    if (s.physical) {
      if (s.physical->initial_stiffness_matrix) {
        k0 = *s.physical->initial_stiffness_matrix;
      } else if (s.physical->initial_stiffness) {
        k0 = Eigen::MatrixXd::Constant(1, 1, *s.physical->initial_stiffness);
      }
    } else {
      k0 = s.Build()->initial_stiffness();
    }
    const long m = static_cast<long>(names.size());
    if (!k0 || k0->rows() != m || k0->cols() != m) {
      fmt::print(stderr, "warning: export-fmu: no initial stiffness K0 is known for {}: inside a "
                         "communication step its restoring force is held (K0 = 0); give "
                         "initial_stiffness in the config for a first-order correction\n", names[0]);
      k0 = Eigen::MatrixXd::Zero(m, m);
    }
    ExportedBlock block{names, {}};
    for (long i = 0; i < m; ++i) {
      block.k0.emplace_back();
      for (long j = 0; j < m; ++j) block.k0.back().push_back((*k0)(i, j));
    }
    blocks.push_back(std::move(block));
  }
  return blocks;
}

// A C identifier from the output file's stem ("rotor-fmu" → "rotor_fmu").
std::string ModelIdentifier(const std::string& out) {
  std::string id = fs::path(out).stem().string();
  for (char& c : id) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  if (id.empty() || std::isdigit(static_cast<unsigned char>(id[0]))) id = "m_" + id;
  return id;
}

void ExportFmu(const ExportFmuOptions& o) {
  if (o.fmi_version != 2 && o.fmi_version != 3) {
    throw ConfigError(fmt::format("--fmi-version {}: give 2 (FMI 2.0, the default) or 3", o.fmi_version));
  }
  const io::SimulationConfig cfg = io::LoadSimulationConfig(o.config);
  std::vector<io::ProtectedFile> inputs;
  for (const auto& f : cfg.files) inputs.push_back({f.path, "the " + f.role + " file"});
  inputs.push_back({o.config, "the config"});
  io::CheckOutputFile(o.out, inputs, "--out");
  // The variable table beside the FMU: rotor.fmu -> rotor.variables.csv.
  const std::string table = (fs::path(o.out).parent_path() /
                             (fs::path(o.out).stem().string() + ".variables.csv")).string();
  io::CheckOutputFile(table, inputs, "--out (its variable table)");
  const io::RunSpec full = io::CompileRunSpec(cfg);
  if (full.scheme.config.adaptive.enabled) {
    throw ConfigError(fmt::format("export-fmu: {}: integrator.adaptive is on; an FMU steps by a "
                                  "fixed communication step: turn it off", o.config));
  }
  const std::vector<ExportedBlock> blocks = ExportedBlocks(full, ConfiguredSlots(cfg.input.root()));

  // The reduced config: the model, its initial state and the integrator (and the duration,
  // which the FMU replaces by the master's stop time).
  const YAML::Node& root = cfg.input.root();
  YAML::Node reduced;
  for (const char* key : {"model", "initial_state", "integrator", "duration"}) {
    if (root[key]) reduced[key] = root[key];
  }
  YAML::Emitter emitter;
  emitter << reduced;
  const std::string reduced_text = std::string("# Reduced by hybridtest export-fmu from ") +
                                   fs::path(o.config).filename().string() + "\n" + emitter.c_str() + "\n";
  // The files it reads keep their paths relative to it, under resources/hybridtest/tree/.
  const fs::path config_abs = fs::absolute(o.config).lexically_normal();
  fs::path base = config_abs.parent_path();
  std::vector<fs::path> files;
  for (const auto& f : cfg.files) {
    if (f.role == "config") continue;
    const fs::path p = fs::absolute(f.path).lexically_normal();
    files.push_back(p);
    while (p.lexically_relative(base).string().starts_with("..")) base = base.parent_path();
  }
  const std::string config_member = "tree/" + config_abs.lexically_relative(base).string();
  const io::RunSpec spec = io::CompileRunSpec(io::ParseSimulationConfig(
      YamlInput::FromText(reduced_text, config_abs.string())));
  const fmu_export::Layout layout = fmu_export::MakeLayout(spec, blocks);

  fmu_export::DescriptionInfo info;
  info.fmi_version = o.fmi_version;
  info.model_identifier = ModelIdentifier(o.out);
  info.model_name = info.model_identifier;  // one name in an importer's list (the config's is
                                            // in the description)
  info.step = spec.scheme.dt;
  info.description = fmt::format("{} ({}), exported by hybridtest export-fmu", spec.model.name,
                                 spec.model.description);
  info.guid = "{hybridtest-" + io::Sha256Hex(reduced_text + nlohmann::json(fmu_export::BlocksToJson(blocks)).dump()).substr(0, 32) + "}";
  const nlohmann::json settings{{"config", config_member},
                                {"blocks", fmu_export::BlocksToJson(blocks)},
                                {"token", info.guid},
                                {"fmi_version", o.fmi_version}};

  const std::string platform = o.fmi_version == 3 ? "x86_64-linux" : "linux64";
  std::vector<std::pair<std::string, std::string>> members{
      {"modelDescription.xml", fmu_export::ModelDescriptionXml(layout, info)},
      {"binaries/" + platform + "/" + info.model_identifier + ".so", Slurp(FmuBinary())},
      {"resources/hybridtest/export.json", settings.dump(2) + "\n"},
      {"resources/hybridtest/" + config_member, reduced_text},
      {"resources/hybridtest/original/" + config_abs.filename().string(), Slurp(o.config)}};
  for (const auto& f : files) {
    members.emplace_back("resources/hybridtest/tree/" + f.lexically_relative(base).string(), Slurp(f));
  }
  fmi::WriteArchive(o.out, members);
  io::WriteFileAtomically(table, fmu_export::VariableTableCsv(layout));
  int inputs_n = 0, outputs_n = 0, parameters_n = 0;
  for (const auto& v : layout.variables) {
    using K = fmu_export::Variable::Kind;
    (v.kind == K::kParameter ? parameters_n : v.kind == K::kInput ? inputs_n : outputs_n)++;
  }
  fmt::print("wrote {}: FMI {}.0 co-simulation FMU '{}' ({} parameters, {} inputs, {} outputs; "
             "communication step {} s)\n", o.out, o.fmi_version, info.model_identifier,
             parameters_n, inputs_n, outputs_n, info.step);
  // The variables a C master addresses by value reference (also in `table`).
  std::size_t width = 4;
  for (const auto& v : layout.variables) width = std::max(width, v.name.size());
  fmt::print("{:<{}}  {:>5}  {:<9}  {}\n", "name", width, "vr", "causality", "unit");
  for (std::size_t vr = 0; vr < layout.variables.size(); ++vr) {
    const auto& v = layout.variables[vr];
    fmt::print("{:<{}}  {:>5}  {:<9}  {}\n", v.name, width, vr, fmu_export::Causality(v),
               v.unit.empty() ? "-" : v.unit);
  }
  fmt::print("variable table: {}\n", table);
}

void AddExportFmuCommand(CLI::App& root) {
  auto o = std::make_shared<ExportFmuOptions>();
  CLI::App* command = root.add_subcommand(
      "export-fmu", "Write the config's model as an FMI co-simulation FMU: its substructured "
                    "slots' restoring forces in, their displacements and q, u out");
  command->add_option("config", o->config, "The run config, e.g. examples/rotor/dummy.yaml")
      ->required()
      ->check(RegularInputFile());
  command->add_option("--out", o->out, "The FMU file to write, e.g. rotor.fmu")->required();
  command->add_option("--fmi-version", o->fmi_version, "2 (FMI 2.0, default) or 3 (FMI 3.0)");
  command->callback([o] { ExportFmu(*o); });
}

const CommandRegistration kReg{"export-fmu", &AddExportFmuCommand};

}  // namespace
}  // namespace hybridtest::app
