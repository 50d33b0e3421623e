// hybridtest equations MODEL_OR_CONFIG [--format markdown|latex|sympy|c] [--out FILE]
//                      [--overwrite] [--paper-form] [--blades N]
// hybridtest compile-model MODEL_OR_CONFIG [--blades N]
// Prints a model's equations of motion symbolically, derived by the engine itself on the
// Symbolic scalar, or as C; compiles that C into the cache (docs/equations.md, decision 0019).
#include <fmt/core.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <iostream>

#include "command.h"
#include "hybridtest/common/error.h"
#include "hybridtest/io/config.h"
#include "hybridtest/io/output_guard.h"
#include "hybridtest/modelfile/model_file.h"
#include "hybridtest/models/catalogue.h"
#include "hybridtest/symbolic/codegen.h"
#include "hybridtest/symbolic/compiled_model.h"
#include "hybridtest/symbolic/equations.h"
#include "hybridtest/symbolic/parameters.h"
#include "hybridtest/symbolic/write_equations.h"

namespace hybridtest::app {
namespace {

struct EquationsOptions {
  std::string model;
  std::string format = "markdown";
  std::string out;
  bool overwrite = false;
  bool paper_form = false;
  bool numeric_parameters = false;
  int blades = 3;
};

using Rebuild = std::function<multibody::Model(const models::ParameterSet&)>;

// A model file's or a built-in model's builder, for rebuilding it with other parameter values
// (symbolic/parameters.h).
Rebuild FileBuilder(const std::string& path) {
  auto file = std::make_shared<modelfile::ModelFile>(modelfile::LoadModelFile(path));
  return [file](const models::ParameterSet& p) { return modelfile::BuildModelFile(*file, p).model; };
}
Rebuild BuiltInBuilder(const std::string& name, int blades) {
  return [name, blades](const models::ParameterSet& p) { return models::BuildModel(name, blades, p).model; };
}

// A model file (it has `coordinates:`), a run config, or a built-in model's name; *rebuild
// rebuilds it from other parameter values, starting from *declared (empty: the resolved ones).
models::BuiltModel LoadModel(const EquationsOptions& opt, std::string* source, Rebuild* rebuild,
                             models::ParameterSet* declared) {
  *source = opt.model;
  std::error_code ec;
  if (!std::filesystem::exists(opt.model, ec)) {
    for (const std::string& name : models::ModelNames()) {
      if (name == opt.model) {
        *source = "built-in model " + name;
        *rebuild = BuiltInBuilder(name, opt.blades);
        // The defaults as declared (per-blade values unset), so that the symbols are the
        // shared ones (m_b, not blade1.m_b) where the model uses one value for every blade.
        *declared = models::DefaultParameters(name, opt.blades);
        return models::BuildModel(name, opt.blades, *declared);
      }
    }
    std::string known;
    for (const std::string& name : models::ModelNames()) known += (known.empty() ? "" : ", ") + name;
    throw ConfigError(fmt::format("equations {}: no such file, and not a built-in model ({}); "
                                  "give a model file, a run config or a built-in model's name",
                                  opt.model, known));
  }
  YAML::Node root;
  try {
    root = YAML::LoadFile(opt.model);
  } catch (const YAML::Exception& e) {
    throw ConfigError(fmt::format("equations {}: cannot read it as YAML (line {}: {}); give a "
                                  "model file or a run config", opt.model, e.mark.line + 1, e.msg));
  }
  if (root.IsMap() && root["coordinates"]) {
    const modelfile::ModelFile file = modelfile::LoadModelFile(opt.model);
    *rebuild = FileBuilder(opt.model);
    return modelfile::BuildModelFile(file, file.parameters);
  }
  models::BuiltModel built = io::LoadSimulationConfig(opt.model).model;
  // The config loaded, so its model section is valid: a file (relative to the config) or a name.
  const YAML::Node model = root["model"];
  if (model["file"]) {
    *rebuild = FileBuilder((std::filesystem::path(opt.model).parent_path() /
                            model["file"].as<std::string>()).string());
  } else {
    const std::string name = model["name"].as<std::string>();
    *rebuild = BuiltInBuilder(name, model["blades"] ? model["blades"].as<int>() : (name == "rotor" ? 3 : 0));
  }
  return built;
}

symbolic::Format ParseFormat(const std::string& format) {
  if (format == "markdown") return symbolic::Format::kMarkdown;
  if (format == "latex") return symbolic::Format::kLatex;
  if (format == "sympy") return symbolic::Format::kSympy;
  throw ConfigError(fmt::format("--format {}: expected markdown, latex, sympy or c", format));
}

std::string Document(const EquationsOptions& opt) {
  std::string source;
  Rebuild rebuild;
  models::ParameterSet declared;
  const models::BuiltModel built = LoadModel(opt, &source, &rebuild, &declared);
  if (opt.format == "c") {
    return symbolic::WriteC(built.model, symbolic::DeriveRhs(built.model), built.name,
                            symbolic::kCompiledFunction).source;
  }
  const symbolic::Format format = ParseFormat(opt.format);
  symbolic::Equations eq = symbolic::DeriveEquations(built.model);
  if (!opt.numeric_parameters) {
    symbolic::SymbolizeParameters(eq, declared.all().empty() ? built.parameters : declared, rebuild);
  }
  symbolic::DocumentInfo info;
  info.model_name = built.name;
  info.description = built.description;
  info.source = source;
  info.paper_form = opt.paper_form;
  for (const auto& p : built.parameters.all()) {
    info.parameters.push_back({p.name, p.value, p.unit, p.description});
  }
  return symbolic::WriteEquations(built.model, eq, info, format);
}

void RunEquations(const EquationsOptions& opt) {
  if (opt.format != "c") ParseFormat(opt.format);  // a bad format before any work
  if (!opt.out.empty()) {
    io::CheckOutputFile(opt.out, {{opt.model, "the model"}}, "--out");
    std::error_code ec;
    if (std::filesystem::exists(opt.out, ec) && !opt.overwrite) {
      throw ConfigError(fmt::format("--out {}: the file exists; give --overwrite to replace it, "
                                    "or another path", opt.out));
    }
  }
  const std::string text = Document(opt);
  if (opt.out.empty()) {
    std::cout << text;
    return;
  }
  std::ofstream os(opt.out, std::ios::trunc);
  os << text;
  if (!os) throw Error(fmt::format("--out {}: cannot write the file", opt.out));
}

void AddEquationsCommand(CLI::App& root) {
  auto opt = std::make_shared<EquationsOptions>();
  CLI::App* cmd = root.add_subcommand(
      "equations", "Print a model's equations of motion symbolically (partial velocities, Fr, "
                   "Fr*, M u̇ = f), derived by the engine itself");
  cmd->add_option("model", opt->model,
                  "model file, run config (YAML) or built-in model name (rotor, ...)")
      ->required();
  cmd->add_option("--format", opt->format,
                  "markdown (default), latex, sympy, or c (the right-hand side as one C function)");
  cmd->add_option("--out", opt->out, "write to this file instead of standard output");
  cmd->add_flag("--overwrite", opt->overwrite, "replace an existing --out file");
  cmd->add_flag("--paper-form", opt->paper_form,
                "also print the paper's form M_p ẋ + g_p = 0 (Eq. 18)");
  cmd->add_flag("--numeric-parameters", opt->numeric_parameters,
                "print the parameters' values instead of their symbols (skips the rebuilds "
                "that recover the symbols)");
  cmd->add_option("--blades", opt->blades, "blade count of the built-in rotor (default 3)");
  cmd->callback([opt] { RunEquations(*opt); });
}

void RunCompileModel(const EquationsOptions& opt) {
  std::string source;
  Rebuild rebuild;
  models::ParameterSet declared;
  const models::BuiltModel built = LoadModel(opt, &source, &rebuild, &declared);
  symbolic::CompileReport report;
  symbolic::CompileModel(built.model, built.name, &report);
  fmt::print("{}\n  {} ({} common subexpressions, {} operations)\n  checked against the numeric "
             "engine at {} random states: largest relative difference {:.2g}\n",
             report.library, report.from_cache ? "found in the cache" : "compiled",
             report.temporaries, report.operations, symbolic::kCheckStates,
             report.largest_difference);
}

void AddCompileModelCommand(CLI::App& root) {
  auto opt = std::make_shared<EquationsOptions>();
  CLI::App* cmd = root.add_subcommand(
      "compile-model", "Compile a model's right-hand side (C from `equations --format c`) into "
                       "the cache of compiled models, check it, and print the library's path");
  cmd->add_option("model", opt->model,
                  "model file, run config (YAML) or built-in model name (rotor, ...)")
      ->required();
  cmd->add_option("--blades", opt->blades, "blade count of the built-in rotor (default 3)");
  cmd->callback([opt] { RunCompileModel(*opt); });
}

const CommandRegistration kRegistration{"equations", &AddEquationsCommand};
const CommandRegistration kCompileRegistration{"compile-model", &AddCompileModelCommand};

}  // namespace
}  // namespace hybridtest::app
