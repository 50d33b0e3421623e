// hybridtest equations MODEL_OR_CONFIG [--format markdown|latex|sympy] [--out FILE]
//                      [--overwrite] [--paper-form] [--blades N]
// Prints a model's equations of motion symbolically, derived by the engine itself on the
// Symbolic scalar (docs/equations.md, decision 0019).
#include <fmt/core.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <iostream>

#include "command.h"
#include "hybridtest/common/error.h"
#include "hybridtest/io/config.h"
#include "hybridtest/io/output_guard.h"
#include "hybridtest/modelfile/model_file.h"
#include "hybridtest/models/catalogue.h"
#include "hybridtest/symbolic/equations.h"
#include "hybridtest/symbolic/write_equations.h"

namespace hybridtest::app {
namespace {

struct EquationsOptions {
  std::string model;
  std::string format = "markdown";
  std::string out;
  bool overwrite = false;
  bool paper_form = false;
  int blades = 3;
};

// A model file (it has `coordinates:`), a run config, or a built-in model's name.
models::BuiltModel LoadModel(const EquationsOptions& opt, std::string* source) {
  *source = opt.model;
  std::error_code ec;
  if (!std::filesystem::exists(opt.model, ec)) {
    for (const std::string& name : models::ModelNames()) {
      if (name == opt.model) {
        *source = "built-in model " + name;
        return models::BuildModel(name, opt.blades, models::DefaultParameters(name, opt.blades));
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
    return modelfile::BuildModelFile(file, file.parameters);
  }
  return io::LoadSimulationConfig(opt.model).model;
}

symbolic::Format ParseFormat(const std::string& format) {
  if (format == "markdown") return symbolic::Format::kMarkdown;
  if (format == "latex") return symbolic::Format::kLatex;
  if (format == "sympy") return symbolic::Format::kSympy;
  throw ConfigError(fmt::format("--format {}: expected markdown, latex or sympy", format));
}

void RunEquations(const EquationsOptions& opt) {
  const symbolic::Format format = ParseFormat(opt.format);
  if (!opt.out.empty()) {
    io::CheckOutputFile(opt.out, {{opt.model, "the model"}}, "--out");
    std::error_code ec;
    if (std::filesystem::exists(opt.out, ec) && !opt.overwrite) {
      throw ConfigError(fmt::format("--out {}: the file exists; give --overwrite to replace it, "
                                    "or another path", opt.out));
    }
  }
  std::string source;
  const models::BuiltModel built = LoadModel(opt, &source);
  const symbolic::Equations eq = symbolic::DeriveEquations(built.model);
  symbolic::DocumentInfo info;
  info.model_name = built.name;
  info.description = built.description;
  info.source = source;
  info.paper_form = opt.paper_form;
  for (const auto& p : built.parameters.all()) {
    info.parameters.push_back({p.name, p.value, p.unit, p.description});
  }
  const std::string text = symbolic::WriteEquations(built.model, eq, info, format);
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
  cmd->add_option("--format", opt->format, "markdown (default), latex or sympy");
  cmd->add_option("--out", opt->out, "write to this file instead of standard output");
  cmd->add_flag("--overwrite", opt->overwrite, "replace an existing --out file");
  cmd->add_flag("--paper-form", opt->paper_form,
                "also print the paper's form M_p ẋ + g_p = 0 (Eq. 18)");
  cmd->add_option("--blades", opt->blades, "blade count of the built-in rotor (default 3)");
  cmd->callback([opt] { RunEquations(*opt); });
}

const CommandRegistration kRegistration{"equations", &AddEquationsCommand};

}  // namespace
}  // namespace hybridtest::app
