// See equations_document.h.
#include "equations_document.h"

#include <fmt/core.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <memory>

#include "hybridtest/common/error.h"
#include "hybridtest/common/yaml_input.h"
#include "hybridtest/io/config.h"
#include "hybridtest/modelfile/model_file.h"
#include "hybridtest/symbolic/codegen.h"
#include "hybridtest/symbolic/compiled_model.h"
#include "hybridtest/symbolic/equations.h"
#include "hybridtest/symbolic/parameters.h"
#include "hybridtest/symbolic/write_equations.h"

namespace hybridtest::app {
namespace {

// A model file's or a built-in model's builder, for rebuilding it with other parameter values
// (symbolic/parameters.h).
Rebuild FileBuilder(std::shared_ptr<const modelfile::ModelFile> file) {
  return [file](const models::ParameterSet& p) { return modelfile::BuildModelFile(*file, p).model; };
}
Rebuild BuiltInBuilder(const std::string& name, int blades) {
  return [name, blades](const models::ParameterSet& p) { return models::BuildModel(name, blades, p).model; };
}

}  // namespace

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
  // Read once, through the shared guard of every YAML input (size, encoding, syntax).
  YamlInput input = YamlInput::FromFile(
      opt.model, "a model file's coordinates:, frames:, … or a run config's model:, integrator:, …");
  const YAML::Node root = input.root();
  if (root["coordinates"]) {
    const auto file = std::make_shared<const modelfile::ModelFile>(
        modelfile::ParseModelFile(std::move(input)));
    *rebuild = FileBuilder(file);
    return modelfile::BuildModelFile(*file, file->parameters);
  }
  models::BuiltModel built = io::LoadSimulationConfig(opt.model).model;
  // The config loaded, so its model section is valid: a file (relative to the config) or a name.
  const YAML::Node model = root["model"];
  if (model["file"]) {
    *rebuild = FileBuilder(std::make_shared<const modelfile::ModelFile>(modelfile::LoadModelFile(
        (std::filesystem::path(opt.model).parent_path() / model["file"].as<std::string>()).string())));
  } else {
    const std::string name = model["name"].as<std::string>();
    *rebuild = BuiltInBuilder(name, model["blades"] ? model["blades"].as<int>() : (name == "rotor" ? 3 : 0));
  }
  return built;
}

void CheckEquationsFormat(const std::string& format) {
  if (format != "c" && format != "markdown" && format != "latex" && format != "sympy") {
    throw ConfigError(fmt::format("--format {}: expected markdown, latex, sympy or c", format));
  }
}

namespace {

symbolic::Format ParseFormat(const std::string& format) {
  CheckEquationsFormat(format);
  if (format == "latex") return symbolic::Format::kLatex;
  if (format == "sympy") return symbolic::Format::kSympy;
  return symbolic::Format::kMarkdown;
}

}  // namespace

std::string EquationsDocument(const EquationsOptions& opt) {
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
  const models::ParameterSet& parameters = declared.all().empty() ? built.parameters : declared;
  if (!opt.numeric_parameters) symbolic::SymbolizeParameters(eq, parameters, rebuild);
  symbolic::DocumentInfo info;
  info.model_name = built.name;
  info.description = built.description;
  info.source = source;
  info.paper_form = opt.paper_form;
  for (const auto& p : built.parameters.all()) {
    // blade2.m_b with m_b's value prints as m_b: listed once, as m_b.
    if (symbolic::IsFollowingInstance(parameters, p.name)) continue;
    info.parameters.push_back({p.name, p.value, p.unit, p.description});
  }
  return symbolic::WriteEquations(built.model, eq, info, format);
}


}  // namespace hybridtest::app
