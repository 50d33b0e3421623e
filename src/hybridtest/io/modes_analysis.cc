// Loading a model's operating point and its modes for every front door. See modes_analysis.h.
#include "hybridtest/io/modes_analysis.h"

#include <fmt/core.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>
#include <optional>

#include "hybridtest/common/error.h"
#include "hybridtest/common/yaml_input.h"
#include "hybridtest/io/config.h"
#include "hybridtest/modelfile/model_file.h"
#include "hybridtest/modelfile/model_file_modes.h"

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

// The index in the linearisation's states of coordinate `name`; ConfigError at `where` when it
// is not an independent coordinate.
std::size_t ReadIndex(const multibody::Model& model, const multibody::Linearization& lin,
                      const std::string& name, const std::string& where) {
  const int n = model.num_coordinates();
  for (std::size_t i = 0; i < lin.states.size(); ++i) {
    if (lin.states[i] < n && lin.state_names[i] == name) return i;
  }
  std::string list;
  for (std::size_t i = 0; i < lin.states.size(); ++i) {
    if (lin.states[i] < n) list += (list.empty() ? "" : ", ") + lin.state_names[i];
  }
  throw ConfigError(fmt::format("{}: '{}' is not an independent coordinate of the model; name "
                                "one of {}", where, name, list));
}

// Normalises each shape on its largest read coordinate and fills the readouts.
std::vector<ModeReadout> ReadModes(const multibody::Model& model,
                                   const modelfile::ModeReading& reading,
                                   multibody::ModeAnalysis& analysis) {
  const multibody::Linearization& lin = analysis.linearization;
  std::vector<std::size_t> read;
  for (std::size_t i = 0; i < reading.coordinates.size(); ++i) {
    read.push_back(ReadIndex(model, lin, reading.coordinates[i], reading.coordinates_where[i]));
  }
  if (read.empty()) {
    for (std::size_t i = 0; i < lin.states.size(); ++i) {
      if (lin.states[i] < model.num_coordinates()) read.push_back(i);
    }
  }
  for (const modelfile::ModeLabel& label : reading.labels) {
    if (!label.dominant.empty()) {
      const std::size_t i = ReadIndex(model, lin, label.dominant, label.where + ".dominant");
      if (std::find(read.begin(), read.end(), i) == read.end()) {
        throw ConfigError(fmt::format("{}.dominant: '{}' is not among modes.coordinates; add it "
                                      "there", label.where, label.dominant));
      }
    }
  }
  double scale = 1.0;
  for (const multibody::Mode& m : analysis.modes) scale = std::max(scale, std::abs(m.eigenvalue));
  const double tol = kModeTolerance * scale;
  std::vector<ModeReadout> out;
  for (multibody::Mode& m : analysis.modes) {
    ModeReadout r;
    r.unstable = m.eigenvalue.real() > tol;
    std::vector<std::size_t> order = read;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      return std::abs(m.shape(static_cast<Eigen::Index>(a))) >
             std::abs(m.shape(static_cast<Eigen::Index>(b)));
    });
    const double top = order.empty() ? 0.0 : std::abs(m.shape(static_cast<Eigen::Index>(order[0])));
    if (top > 1e-12 * m.shape.cwiseAbs().maxCoeff()) {
      m.shape /= m.shape(static_cast<Eigen::Index>(order[0]));
    }
    if (std::abs(m.eigenvalue) > tol && top > 0.0) {
      for (std::size_t i : order) {
        if (std::abs(m.shape(static_cast<Eigen::Index>(i))) < 0.5) break;
        r.dominant.push_back(lin.state_names[i]);
      }
      const bool oscillatory = std::abs(m.eigenvalue.imag()) > tol;
      for (const modelfile::ModeLabel& label : reading.labels) {
        if (label.oscillatory && *label.oscillatory != oscillatory) continue;
        if (!label.dominant.empty() &&
            (r.dominant.empty() || label.dominant != r.dominant.front())) {
          continue;
        }
        r.label = label.name;
        break;
      }
    }
    out.push_back(std::move(r));
  }
  return out;
}

}  // namespace

namespace {
// LoadModesModel, and the model file behind the request (itself, or a run config's
// model.file; none for a built-in model) in `file`. The request is parsed once: a model
// file's tree, or a run config's, is the one read here.
models::BuiltModel LoadModel(const ModesRequest& request, Eigen::VectorXd* x0,
                             std::optional<modelfile::ModelFile>* file) {
  // Through the shared guard of every YAML input (size, encoding, syntax).
  YamlInput input = YamlInput::FromFile(
      request.path, "a model file's coordinates:, … or a run config's model:, …");
  models::ParameterSet parameters;
  std::optional<Eigen::VectorXd> config_x0;
  if (input.root().IsMap() && input.root()["coordinates"]) {
    *file = modelfile::ParseModelFile(std::move(input));
    parameters = (*file)->parameters;
  } else {
    // A run config, from the tree read above; its model file is where the config found it.
    SimulationConfig cfg = ParseSimulationConfig(input);
    const auto model_file = std::find_if(cfg.files.begin(), cfg.files.end(),
                                         [](const RunInput& f) { return f.role == "model"; });
    if (model_file != cfg.files.end()) *file = modelfile::LoadModelFile(model_file->path);
    if (request.set.empty()) {
      *x0 = cfg.x0;
      ApplyStart(request, cfg.model.model.num_coordinates(), *x0);
      return std::move(cfg.model);
    }
    if (!*file) {
      throw ConfigError(fmt::format("modes {}: parameter overrides need a model file (the "
                                    "config names a built-in model); give its parameters "
                                    "under model.parameters instead", request.path));
    }
    parameters = cfg.model.parameters;
    if (input.root()["initial_state"]) config_x0 = cfg.x0;
  }
  for (const auto& [name, value] : request.set) {
    parameters.Set(name, value, fmt::format("modes {}: parameter override {}", request.path, name));
  }
  models::BuiltModel built = modelfile::BuildModelFile(**file, parameters);
  *x0 = config_x0 ? *config_x0 : built.model.initial_state();
  ApplyStart(request, built.model.num_coordinates(), *x0);
  return built;
}
}  // namespace

models::BuiltModel LoadModesModel(const ModesRequest& request, Eigen::VectorXd* x0) {
  std::optional<modelfile::ModelFile> file;
  return LoadModel(request, x0, &file);
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
  std::optional<modelfile::ModelFile> file;
  models::BuiltModel built = LoadModel(request, &start, &file);
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
  const modelfile::ModeReading reading =
      file ? modelfile::ReadModeReading(file->input) : modelfile::ModeReading{};
  std::vector<ModeReadout> readouts = ReadModes(model, reading, analysis);
  ModesReport report{std::move(built), std::move(start), std::move(steady), std::move(analysis),
                     std::move(readouts), {}, true};
  if (!report.steady) {
    report.residual = multibody::CalcSpeedRateResidual(report.built.model, request.time,
                                                       report.analysis.x,
                                                       report.built.slot_stiffness);
    report.equilibrium = report.residual.residual <= kEquilibriumTolerance;
  }
  return report;
}

}  // namespace hybridtest::io
