// Loading a model's operating point and its modes for every front door. See modes_analysis.h.
#include "hybridtest/io/modes_analysis.h"

#include <fmt/core.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>

#include "hybridtest/common/error.h"
#include "hybridtest/io/config.h"
#include "hybridtest/modelfile/model_file.h"

namespace hybridtest::io {

namespace {

void ApplyStart(const ModesRequest& request, int n, Eigen::VectorXd& x) {
  for (int part = 0; part < 2; ++part) {
    const std::optional<std::vector<double>>& values = part == 0 ? request.q : request.u;
    if (!values) continue;
    if (static_cast<int>(values->size()) != n) {
      throw ConfigError(fmt::format("modes {}: {} has {} values; the model has n = {}: give "
                                    "one value per {} (SI)", request.path, part ? "u" : "q",
                                    values->size(), n, part ? "speed" : "coordinate"));
    }
    for (int k = 0; k < n; ++k) x(part * n + k) = (*values)[static_cast<std::size_t>(k)];
  }
}

}  // namespace

models::BuiltModel LoadModesModel(const ModesRequest& request, Eigen::VectorXd* x0) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(request.path);
  } catch (const YAML::Exception& e) {
    throw ConfigError(fmt::format("modes {}: cannot read it as YAML ({}); give a model file or "
                                  "a run config", request.path, e.what()));
  }
  std::string model_file;
  models::ParameterSet parameters;
  std::optional<Eigen::VectorXd> config_x0;
  if (root.IsMap() && root["coordinates"]) {
    model_file = request.path;
    parameters = modelfile::LoadModelFile(model_file).parameters;
  } else {
    SimulationConfig cfg = LoadSimulationConfig(request.path);
    if (request.set.empty()) {
      *x0 = cfg.x0;
      ApplyStart(request, cfg.model.model.num_coordinates(), *x0);
      return std::move(cfg.model);
    }
    if (!root["model"] || !root["model"]["file"]) {
      throw ConfigError(fmt::format("modes {}: parameter overrides need a model file (the "
                                    "config names a built-in model); give its parameters "
                                    "under model.parameters instead", request.path));
    }
    model_file = (std::filesystem::path(request.path).parent_path() /
                  root["model"]["file"].as<std::string>()).string();
    parameters = cfg.model.parameters;
    if (root["initial_state"]) config_x0 = cfg.x0;
  }
  for (const auto& [name, value] : request.set) {
    parameters.Set(name, value, fmt::format("modes {}: parameter override {}", request.path, name));
  }
  models::BuiltModel built =
      modelfile::BuildModelFile(modelfile::LoadModelFile(model_file), parameters);
  *x0 = config_x0 ? *config_x0 : built.model.initial_state();
  ApplyStart(request, built.model.num_coordinates(), *x0);
  return built;
}

std::vector<int> QuantityIndices(const std::vector<multibody::QuantityInfo>& known,
                                 const std::vector<std::string>& names, const std::string& kind,
                                 const std::string& where) {
  std::vector<int> out;
  for (const std::string& name : names) {
    const auto at =
        std::find_if(known.begin(), known.end(), [&](const auto& q) { return q.name == name; });
    if (at == known.end()) {
      std::string list;
      for (const auto& q : known) list += (list.empty() ? "" : ", ") + q.name;
      throw ConfigError(fmt::format("{}: '{}' is not a {} of the model; its {}s are {}", where,
                                    name, kind, kind, list));
    }
    out.push_back(static_cast<int>(at - known.begin()));
  }
  return out;
}

ModesReport AnalyseModes(const ModesRequest& request) {
  Eigen::VectorXd start;
  models::BuiltModel built = LoadModesModel(request, &start);
  const multibody::Model& model = built.model;
  std::optional<multibody::SteadyState> steady;
  multibody::ModeAnalysis analysis;
  try {
    Eigen::VectorXd x = start;
    if (!request.driven.empty() && request.steady.empty()) {
      throw ConfigError(fmt::format("modes {}: driven speeds only matter for a steady state; "
                                    "name the coordinates to solve for (--steady, steady=)",
                                    request.path));
    }
    if (!request.steady.empty()) {
      const std::vector<int> free = QuantityIndices(
          model.coordinates(), request.steady, "coordinate",
          fmt::format("modes {}: steady", request.path));
      multibody::SteadyStateOptions options = request.steady_options;
      options.driven_speeds = QuantityIndices(model.speeds(), request.driven, "speed",
                                              fmt::format("modes {}: driven", request.path));
      steady = multibody::FindSteadyState(model, request.time, x, free, built.slot_stiffness,
                                          options);
      if (!steady->converged) throw ModelError(steady->message);
      x = steady->x;
    }
    analysis = multibody::CalcModes(model, request.time, x, built.slot_stiffness);
  } catch (const ModelError& e) {
    throw ModelError(fmt::format("modes {}: at the operating point: {}", request.path, e.what()));
  }
  return ModesReport{std::move(built), std::move(start), std::move(steady), std::move(analysis)};
}

}  // namespace hybridtest::io
