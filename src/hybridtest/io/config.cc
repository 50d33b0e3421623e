// See config.h.
#include "hybridtest/io/config.h"

#include <fmt/core.h>

#include "hybridtest/multibody/assembly.h"

#include <cmath>
#include <filesystem>

#include "hybridtest/common/error.h"
#include "hybridtest/integrators/catalogue.h"
#include "hybridtest/modelfile/model_file.h"
#include "hybridtest/symbolic/compiled_model.h"

namespace hybridtest::io {

namespace {
// The most stages a user tableau may have: explicit methods in use have at most 17 (Feagin's
// order 10); the bound keeps an s×s matrix small.
constexpr int kMaxStages = 64;

// Applies `model.parameters` overrides to `parameters`; returns the overrides node.
YAML::Node ApplyOverrides(const YamlInput& in, const YAML::Node& node,
                          models::ParameterSet& parameters) {
  const YAML::Node overrides = in.Mapping(node, "parameters", "model.parameters", false);
  if (overrides.IsDefined()) {
    for (const auto& kv : overrides) {
      const std::string key = in.String(kv.first, "model.parameters", "a parameter name");
      const std::string path = "model.parameters." + key;
      const double value = in.Number(kv.second, path, "a number in SI units");
      parameters.Set(key, value, in.Where(kv.second, path));
    }
  }
  return overrides;
}

// `model: {..., compiled: true}`: the model's right-hand side compiled to machine code, from
// the cache or built now, checked against the engine and attached (symbolic/compiled_model.h,
// docs/equations.md). `compiled: false` or no key: the numeric engine.
void AttachCompiledIfAsked(const YamlInput& in, const YAML::Node& node, models::BuiltModel& built) {
  if (!node["compiled"]) return;
  const std::string value = in.String(node["compiled"], "model.compiled", "true or false");
  if (value != "true" && value != "false") {
    in.ThrowValue(node["compiled"], "model.compiled", "true or false");
  }
  if (value == "true") built.model.AttachCompiledRhs(symbolic::CompileModel(built.model, built.name));
}

// `model: {file: PATH, parameters: {...}}`: a model file, PATH relative to the run config.
models::BuiltModel ParseModelFileSection(const YamlInput& in, const YAML::Node& node,
                                         std::vector<RunInput>* files) {
  in.CheckKeys(node, "model", {"file", "parameters", "compiled"});
  const std::string file = in.String(node["file"], "model.file", "the path of a model file");
  std::filesystem::path path(file);
  if (path.is_relative() && !in.path().empty()) {
    path = std::filesystem::path(in.path()).parent_path() / path;
  }
  if (!std::filesystem::exists(path)) {
    throw ConfigError(fmt::format("{} = '{}': no such model file ({}); the path is relative to "
                                  "the run config", in.Where(node["file"], "model.file"), file,
                                  path.string()));
  }
  const std::string model_path = path.lexically_normal().string();
  const modelfile::ModelFile model_file = modelfile::LoadModelFile(model_path);
  models::ParameterSet parameters = model_file.parameters;
  ApplyOverrides(in, node, parameters);
  std::vector<std::string> tables;
  models::BuiltModel built = modelfile::BuildModelFile(model_file, parameters, &tables);
  AttachCompiledIfAsked(in, node, built);
  if (files != nullptr) {
    files->push_back({"model", model_path});
    for (std::string& table : tables) files->push_back({"table", std::move(table)});
  }
  return built;
}
}  // namespace

models::BuiltModel ParseModel(const YamlInput& in, const YAML::Node& node, int* blades_out,
                              std::vector<RunInput>* files) {
  if (node["file"]) {
    if (blades_out != nullptr) *blades_out = 0;
    return ParseModelFileSection(in, node, files);
  }
  in.CheckKeys(node, "model", {"name", "file", "blades", "parameters", "compiled"});
  const std::string name =
      in.String(node["name"], "model.name", "a model name: rotor, double_pendulum or spinning_top");
  int blades = 0;
  if (node["blades"]) {
    if (name != "rotor") {
      throw ConfigError(fmt::format("{}: only the rotor model has blades; remove this key",
                                    in.Where(node["blades"], "model.blades")));
    }
    // Bounded before anything is allocated, by the bound every front shares.
    blades = models::CheckRotorBlades(
        in.Number(node["blades"], "model.blades", "a whole number of blades"),
        in.Where(node["blades"], "model.blades"));
  } else if (name == "rotor") {
    blades = 3;
  }
  models::ParameterSet parameters;
  try {
    parameters = models::DefaultParameters(name, blades);
  } catch (const ConfigError& e) {
    throw ConfigError(fmt::format("{}: {}", in.Where(node["name"], "model.name"), e.what()));
  }
  const YAML::Node overrides = ApplyOverrides(in, node, parameters);
  if (blades_out != nullptr) *blades_out = blades;
  try {
    models::BuiltModel built = models::BuildModel(name, blades, parameters);
    AttachCompiledIfAsked(in, node, built);
    return built;
  } catch (const ConfigError& e) {
    // A value the model rejects: point at the overrides (or the model section).
    const YAML::Node& at = overrides.IsDefined() ? overrides : node;
    throw ConfigError(at.Mark().line >= 0
                          ? fmt::format("{}:{}: {}", in.path(), at.Mark().line + 1, e.what())
                          : fmt::format("{}: {}", in.path(), e.what()));
  }
}

integrators::ButcherTableau ParseTableau(const YamlInput& in, const YAML::Node& node,
                                         std::string_view key_path) {
  if (node.IsScalar()) {
    try {
      return integrators::FindTableau(node.as<std::string>());
    } catch (const ConfigError& e) {
      throw ConfigError(fmt::format("{}: {}", in.Where(node, key_path), e.what()));
    }
  }
  if (!node.IsMap()) {
    throw ConfigError(fmt::format("{}: expected a tableau name (e.g. heun, rk4) or a mapping "
                                  "with a, b, c and order", in.Where(node, key_path)));
  }
  const std::string kp(key_path);
  in.CheckKeys(node, kp, {"name", "title", "a", "b", "c", "order"});
  integrators::ButcherTableau t;
  t.name = node["name"] ? in.String(node["name"], kp + ".name", "a name") : "user";
  t.title = node["title"] ? in.String(node["title"], kp + ".title", "a title") : "user tableau";
  const std::vector<double> b = in.Numbers(node["b"], kp + ".b", "weights b_i");
  const std::vector<double> c = in.Numbers(node["c"], kp + ".c", "nodes c_i");
  const YAML::Node a = node["a"];
  // A const node's absent key is an invalid node, on which IsSequence() throws a YAML
  // exception (found by fuzzing): test that it is there first.
  if (!a.IsDefined() || a.IsNull() || !a.IsSequence()) {
    throw ConfigError(fmt::format("{}: {}; expected the s×s matrix a as a list of rows [[..], "
                                  "[..]], one row per stage (s = {}, the length of b): add `a:` "
                                  "under {}", in.Where(a.IsDefined() ? a : node, kp + ".a"),
                                  a.IsDefined() ? "not a list of rows" : "missing", b.size(), kp));
  }
  // Sized before anything is allocated: an s×s matrix of s up to the list bound would take
  // tens of gigabytes.
  if (b.size() < 1 || b.size() > static_cast<std::size_t>(kMaxStages)) {
    in.ThrowValue(node["b"], kp + ".b",
                  fmt::format("1 to {} weights b_i (one per stage)", kMaxStages));
  }
  if (a.size() != b.size() || c.size() != b.size()) {
    throw ConfigError(fmt::format("{}: a has {} rows and c {} entries for the {} weights of b; "
                                  "give s = {} of each (one per stage)", in.Where(node, kp),
                                  a.size(), c.size(), b.size(), b.size()));
  }
  const int s = static_cast<int>(b.size());
  t.b = Eigen::Map<const Eigen::VectorXd>(b.data(), s);
  t.c = Eigen::Map<const Eigen::VectorXd>(c.data(), static_cast<Eigen::Index>(c.size()));
  t.a.setZero(static_cast<Eigen::Index>(a.size()), s);
  for (std::size_t i = 0; i < a.size(); ++i) {
    const std::vector<double> row = in.Numbers(a[i], fmt::format("{}.a[{}]", kp, i), "a_ij");
    if (static_cast<int>(row.size()) != s) {
      throw ConfigError(fmt::format("{}: row {} of a has {} entries; expected s = {} (the length "
                                    "of b)", in.Where(a[i], kp + ".a"), i, row.size(), s));
    }
    for (int j = 0; j < s; ++j) t.a(static_cast<Eigen::Index>(i), j) = row[j];
  }
  t.order = in.Integer(node["order"], kp + ".order", "the claimed order p (1 to 4)");
  integrators::ValidateTableau(t, in.Where(node, kp));
  return t;
}

schemes::SchemeConfig ParseScheme(const YamlInput& in, const YAML::Node& integ) {
  in.CheckKeys(integ, "integrator", {"scheme", "tableau", "dt", "alpha", "adaptive", "substep"});
  schemes::SchemeConfig sc;
  const std::string name = integ["scheme"]
                               ? in.String(integ["scheme"], "integrator.scheme",
                                           "runge-kutta, alpha-os or mr-os")
                               : "runge-kutta";
  if (name == "runge-kutta") {
    sc.kind = schemes::SchemeKind::kRungeKutta;
  } else if (name == "alpha-os") {
    sc.kind = schemes::SchemeKind::kAlphaOs;
  } else if (name == "mr-os") {
    sc.kind = schemes::SchemeKind::kMrOs;
  } else {
    throw ConfigError(fmt::format("{} = '{}': expected runge-kutta (explicit, any tableau), "
                                  "alpha-os (operator splitting, one specimen evaluation per step) "
                                  "or mr-os (multi-rate operator splitting)",
                                  in.Where(integ["scheme"], "integrator.scheme"), name));
  }
  auto only_for = [&](const char* key, bool allowed, const char* schemes_list) {
    if (integ[key] && !allowed) {
      throw ConfigError(fmt::format("{}: `{}` applies to scheme {} only; remove it or change the "
                                    "scheme", in.Where(integ[key], std::string("integrator.") + key),
                                    key, schemes_list));
    }
  };
  const bool os = sc.kind != schemes::SchemeKind::kRungeKutta;
  only_for("alpha", sc.kind == schemes::SchemeKind::kAlphaOs, "alpha-os");
  only_for("adaptive", os, "alpha-os or mr-os");
  only_for("substep", sc.kind == schemes::SchemeKind::kMrOs, "mr-os");
  if (integ["alpha"]) {
    sc.alpha = in.Number(integ["alpha"], "integrator.alpha", "α between -1/3 and 0");
    if (!(sc.alpha >= -1.0 / 3.0 - 1e-12 && sc.alpha <= 0.0)) {
      throw ConfigError(fmt::format("{} = {}: expected α in [-1/3, 0] (0: no numerical damping; "
                                    "-0.05 is a common choice)",
                                    in.Where(integ["alpha"], "integrator.alpha"), sc.alpha));
    }
  }
  if (integ["substep"]) {
    sc.substep = in.PositiveNumber(integ["substep"], "integrator.substep",
                                   "the largest RK4 substep of the numerical model in seconds");
  }
  if (integ["adaptive"]) {
    const YAML::Node a = in.Mapping(integ, "adaptive", "integrator.adaptive", true);
    in.CheckKeys(a, "integrator.adaptive", {"tolerance", "dt_min", "dt_max"});
    sc.adaptive.enabled = true;
    if (a["tolerance"]) {
      sc.adaptive.tolerance = in.PositiveNumber(a["tolerance"], "integrator.adaptive.tolerance",
                                                "the local error per step in m (e.g. 2e-6)");
    }
    if (a["dt_min"]) {
      sc.adaptive.dt_min = in.PositiveNumber(a["dt_min"], "integrator.adaptive.dt_min",
                                             "the smallest step in seconds");
    }
    if (a["dt_max"]) {
      sc.adaptive.dt_max = in.PositiveNumber(a["dt_max"], "integrator.adaptive.dt_max",
                                             "the largest step in seconds");
    }
    if (sc.adaptive.dt_min > sc.adaptive.dt_max) {
      throw ConfigError(fmt::format("{}: dt_min = {} s > dt_max = {} s; expected dt_min ≤ dt_max",
                                    in.Where(a, "integrator.adaptive"), sc.adaptive.dt_min,
                                    sc.adaptive.dt_max));
    }
  }
  return sc;
}

namespace {
// The `test:` block as JSON: mappings and lists as they are, every scalar as its text (the
// record keeps what the operator wrote: "S-0421", "0042", "2026-11-23").
nlohmann::json TestRecord(const YamlInput& in, const YAML::Node& node, const std::string& kp) {
  if (node.IsMap()) {
    nlohmann::json out = nlohmann::json::object();
    for (const auto& kv : node) {
      const std::string key = in.String(kv.first, kp, "a key (a name such as specimen)");
      out[key] = TestRecord(in, kv.second, kp + "." + key);
    }
    return out;
  }
  if (node.IsSequence()) {
    nlohmann::json out = nlohmann::json::array();
    for (std::size_t i = 0; i < node.size(); ++i) {
      out.push_back(TestRecord(in, node[i], fmt::format("{}[{}]", kp, i)));
    }
    return out;
  }
  if (node.IsNull()) return nullptr;
  return node.Scalar();
}
}  // namespace

SimulationConfig ParseSimulationConfig(const YamlInput& in) {
  const YAML::Node& root = in.root();
  in.CheckKeys(root, "", {"model", "initial_state", "integrator", "duration", "output",
                          "substructures", "progress", "resume", "test", "real_time", "start"});
  int blades = 0;
  std::vector<RunInput> files;
  models::BuiltModel model =
      ParseModel(in, in.Mapping(root, "model", "model", true), &blades, &files);
  SimulationConfig cfg{.input = in, .model = std::move(model), .blades = blades, .x0 = {},
                       .tableau = {}, .scheme = {}, .dt = 0.0, .duration = 0.0, .steps = 0, .output_csv = {},
                       .quiet = false, .resume_force_tolerance = std::nullopt,
                       .resume_position_tolerance = std::nullopt};
  const int n = cfg.model.model.num_coordinates();

  // Initial state: zero unless given (the paper states none; see PAPER-NOTES).
  // The model's own initial state (zero unless a model file gives `initial:`; z(0) from the
  // model's states).
  cfg.x0 = cfg.model.model.initial_state();
  const YAML::Node init = in.Mapping(root, "initial_state", "initial_state", false);
  if (init.IsDefined()) {
    in.CheckKeys(init, "initial_state", {"q", "u"});
    for (const char* key : {"q", "u"}) {
      if (!init[key]) continue;
      const std::string path = std::string("initial_state.") + key;
      const std::vector<double> v = in.Numbers(init[key], path, "numbers in SI units");
      if (static_cast<int>(v.size()) != n) {
        throw ConfigError(fmt::format("{}: has {} entries; the {} model has n = {} ({})",
                                      in.Where(init[key], path), v.size(), cfg.model.name, n,
                                      key[0] == 'q' ? "coordinates" : "speeds"));
      }
      cfg.x0.segment(key[0] == 'q' ? 0 : n, n) = Eigen::Map<const Eigen::VectorXd>(v.data(), n);
    }
  }
  if (cfg.model.model.has_constraints()) {
    // Dependent coordinates and speeds solved from the independent ones (assembly.h).
    try {
      cfg.x0 = multibody::AssembleState(cfg.model.model, 0.0, cfg.x0).x;
    } catch (const ModelError& e) {
      throw ConfigError(fmt::format("{}: {}", in.Where(init.IsDefined() ? init : root,
                                                       "initial_state"), e.what()));
    }
  }

  const YAML::Node integ = in.Mapping(root, "integrator", "integrator", true);
  cfg.scheme = ParseScheme(in, integ);
  if (cfg.scheme.kind == schemes::SchemeKind::kRungeKutta) {
    if (!integ["tableau"]) {
      throw ConfigError(fmt::format("{}: missing; expected a tableau name such as heun or rk4",
                                    in.Where(integ, "integrator.tableau")));
    }
    cfg.tableau = ParseTableau(in, integ["tableau"], "integrator.tableau");
  } else {
    if (integ["tableau"]) {
      throw ConfigError(fmt::format("{}: the {} scheme has no tableau; remove this key (tableaux "
                                    "belong to scheme: runge-kutta)",
                                    in.Where(integ["tableau"], "integrator.tableau"),
                                    schemes::SchemeKindName(cfg.scheme.kind)));
    }
    cfg.tableau = integrators::FindTableau("rk4");  // MR-OS substeps; recorded in the sidecar
  }
  cfg.dt = in.PositiveNumber(integ["dt"], "integrator.dt", "a positive time step in seconds");
  cfg.duration = in.PositiveNumber(root["duration"], "duration",
                                   "a positive simulated duration in seconds");
  // The step count is range-checked before it is converted (duration: 1e19 must not wrap).
  const double ratio = cfg.duration / cfg.dt;
  if (!(ratio <= static_cast<double>(kMaxSteps))) {
    throw ConfigError(fmt::format("{}: duration {} s with dt = {} s gives {:.3g} steps; at most {} "
                                  "are allowed: shorten the duration or enlarge dt",
                                  in.Where(root["duration"], "duration"), cfg.duration, cfg.dt,
                                  ratio, kMaxSteps));
  }
  const double steps = std::round(ratio);
  if (!cfg.scheme.adaptive.enabled && std::abs(steps * cfg.dt - cfg.duration) > 1e-9 * cfg.duration) {
    throw ConfigError(fmt::format("{}: duration {} s is not a whole number of steps of dt = {} s; "
                                  "choose a duration that is a multiple of dt",
                                  in.Where(root["duration"], "duration"), cfg.duration, cfg.dt));
  }
  if (steps < 1) {
    throw ConfigError(fmt::format("{}: duration {} s is shorter than one step of dt = {} s",
                                  in.Where(root["duration"], "duration"), cfg.duration, cfg.dt));
  }
  cfg.steps = static_cast<long>(steps);

  const YAML::Node output = in.Mapping(root, "output", "output", false);
  if (output.IsDefined()) {
    in.CheckKeys(output, "output", {"csv"});
    if (output["csv"]) cfg.output_csv = in.String(output["csv"], "output.csv", "a file path");
  }
  const YAML::Node progress = in.Mapping(root, "progress", "progress", false);
  if (progress.IsDefined()) {
    in.CheckKeys(progress, "progress", {"quiet"});
    if (progress["quiet"]) {
      // true or false only: `maybe` (or a typo) silently meaning false would be a lie.
      const std::string quiet = in.String(progress["quiet"], "progress.quiet", "true or false");
      if (quiet != "true" && quiet != "false") {
        in.ThrowValue(progress["quiet"], "progress.quiet", "true or false");
      }
      cfg.quiet = quiet == "true";
    }
  }
  const YAML::Node resume = in.Mapping(root, "resume", "resume", false);
  if (resume.IsDefined()) {
    in.CheckKeys(resume, "resume", {"force_tolerance", "position_tolerance"});
    if (resume["position_tolerance"]) {
      cfg.resume_position_tolerance = in.PositiveNumber(
          resume["position_tolerance"], "resume.position_tolerance",
          "a positive distance in m (largest |measured - committed position| on resume)");
    }
    if (resume["force_tolerance"]) {
      cfg.resume_force_tolerance = in.PositiveNumber(
          resume["force_tolerance"], "resume.force_tolerance",
          "a positive force in newtons (largest |measured - committed force| on resume)");
    }
  }
  if (root["start"]) {
    const std::string start = in.String(root["start"], "start", "check or ramp");
    if (start != "check" && start != "ramp") in.ThrowValue(root["start"], "start", "check or ramp");
    cfg.start_ramp = start == "ramp";
  }
  const YAML::Node test = in.Mapping(root, "test", "test", false);
  if (test.IsDefined()) cfg.test = TestRecord(in, test, "test");
  cfg.files = std::move(files);
  return cfg;
}

SimulationConfig LoadSimulationConfig(const std::string& path) {
  SimulationConfig cfg =
      ParseSimulationConfig(YamlInput::FromFile(path, "keys such as model:, integrator:, duration:"));
  cfg.files.insert(cfg.files.begin(), RunInput{"config", path});
  return cfg;
}

}  // namespace hybridtest::io
