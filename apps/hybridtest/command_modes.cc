// hybridtest modes MODEL_OR_CONFIG [--at q=...,u=...] [--set NAME=VALUE ...] [--time T] [--json]
// Linearises the model about an operating point (through its constraints: the state matrix
// in the independent states) and prints the eigenvalues, natural and damped frequencies,
// damping ratios and mode shapes (multibody/modes.h). The operating point is the model's
// initial state (a model file's `initial:` values, or a run config's initial_state),
// assembled, unless --at gives q and/or u.
#include <fmt/core.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli_values.h"
#include "command.h"
#include "hybridtest/common/error.h"
#include "hybridtest/io/config.h"
#include "hybridtest/modelfile/model_file.h"
#include "hybridtest/multibody/modes.h"

namespace hybridtest::app {
namespace {

struct ModesOptions {
  std::string model;
  std::string at;
  std::vector<std::string> set;
  double time = 0.0;
  bool json = false;
};

// The model (with --set applied) and its operating point.
models::BuiltModel LoadModel(const ModesOptions& opt, Eigen::VectorXd* x0) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(opt.model);
  } catch (const YAML::Exception& e) {
    throw ConfigError(fmt::format("modes {}: cannot read it as YAML ({}); give a model file or "
                                  "a run config", opt.model, e.what()));
  }
  std::string model_file;
  models::ParameterSet parameters;
  std::optional<Eigen::VectorXd> config_x0;
  if (root.IsMap() && root["coordinates"]) {
    model_file = opt.model;
    parameters = modelfile::LoadModelFile(model_file).parameters;
  } else {
    const io::SimulationConfig cfg = io::LoadSimulationConfig(opt.model);
    if (opt.set.empty()) {
      *x0 = cfg.x0;
      return cfg.model;
    }
    if (!root["model"] || !root["model"]["file"]) {
      throw ConfigError(fmt::format("modes {}: --set needs a model file (the config names a "
                                    "built-in model); give its parameters under "
                                    "model.parameters instead", opt.model));
    }
    model_file = (std::filesystem::path(opt.model).parent_path() /
                  root["model"]["file"].as<std::string>()).string();
    parameters = cfg.model.parameters;
    if (root["initial_state"]) config_x0 = cfg.x0;
  }
  for (const std::string& item : opt.set) {
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos) {
      throw ConfigError(fmt::format("--set {}: expected NAME=VALUE (a parameter, SI)", item));
    }
    const std::vector<double> v = ParseNumberList(item.substr(eq + 1), "--set " + item);
    if (v.size() != 1) throw ConfigError(fmt::format("--set {}: expected one number", item));
    parameters.Set(item.substr(0, eq), v[0], "--set " + item);
  }
  models::BuiltModel built =
      modelfile::BuildModelFile(modelfile::LoadModelFile(model_file), parameters);
  *x0 = config_x0 ? *config_x0 : built.model.initial_state();
  return built;
}

// --at q=a,b,...,u=c,d,...: either part may be left out.
void ApplyAt(const std::string& at, int n, Eigen::VectorXd& x) {
  if (at.empty()) return;
  std::vector<double>* target = nullptr;
  std::vector<double> q, u;
  std::string token;
  std::stringstream ss(at);
  while (std::getline(ss, token, ',')) {
    if (token.rfind("q=", 0) == 0) {
      target = &q;
      token = token.substr(2);
    } else if (token.rfind("u=", 0) == 0) {
      target = &u;
      token = token.substr(2);
    }
    if (target == nullptr) {
      throw ConfigError(fmt::format("--at {}: expected q=v1,...,vn and/or u=v1,...,vn", at));
    }
    target->push_back(ParseNumberList(token, "--at")[0]);
  }
  for (const auto* part : {&q, &u}) {
    if (!part->empty() && static_cast<int>(part->size()) != n) {
      throw ConfigError(fmt::format("--at {}: {} has {} values; the model has n = {}", at,
                                    part == &q ? "q" : "u", part->size(), n));
    }
  }
  for (int k = 0; k < n && !q.empty(); ++k) x(k) = q[static_cast<std::size_t>(k)];
  for (int k = 0; k < n && !u.empty(); ++k) x(n + k) = u[static_cast<std::size_t>(k)];
}

void RunModes(const ModesOptions& opt) {
  Eigen::VectorXd x0;
  const models::BuiltModel built = LoadModel(opt, &x0);
  const multibody::Model& model = built.model;
  ApplyAt(opt.at, model.num_coordinates(), x0);
  multibody::ModeAnalysis a;
  try {
    a = multibody::CalcModes(model, opt.time, x0, built.slot_stiffness);
  } catch (const ModelError& e) {
    throw ConfigError(fmt::format("modes {}: at the operating point: {}", opt.model, e.what()));
  }
  const auto& lin = a.linearization;
  if (opt.json) {
    nlohmann::json out;
    out["model"] = built.name;
    out["states"] = lin.state_names;
    out["operating_point"] = std::vector<double>(a.x.data(), a.x.data() + a.x.size());
    out["state_matrix"] = nlohmann::json::array();
    for (Eigen::Index i = 0; i < lin.A.rows(); ++i) {
      std::vector<double> row(lin.A.cols());
      for (Eigen::Index j = 0; j < lin.A.cols(); ++j) row[static_cast<std::size_t>(j)] = lin.A(i, j);
      out["state_matrix"].push_back(row);
    }
    out["modes"] = nlohmann::json::array();
    for (const multibody::Mode& m : a.modes) {
      nlohmann::json j;
      j["real"] = m.eigenvalue.real();
      j["imag"] = m.eigenvalue.imag();
      j["frequency_hz"] = m.frequency_hz;
      j["damped_frequency_hz"] = m.damped_frequency_hz;
      j["damping_ratio"] = m.damping_ratio;
      j["shape_real"] = std::vector<double>();
      j["shape_imag"] = std::vector<double>();
      for (Eigen::Index i = 0; i < m.shape.size(); ++i) {
        j["shape_real"].push_back(m.shape(i).real());
        j["shape_imag"].push_back(m.shape(i).imag());
      }
      out["modes"].push_back(j);
    }
    std::cout << out.dump() << "\n";
    return;
  }
  fmt::print("model {}: linearised at t = {} s about x = [", built.name, opt.time);
  for (Eigen::Index i = 0; i < a.x.size(); ++i) fmt::print("{}{:.6g}", i ? ", " : "", a.x(i));
  fmt::print("]\nindependent states ({}):", lin.state_names.size());
  for (const std::string& s : lin.state_names) fmt::print(" {}", s);
  fmt::print("\nstate matrix A (ẋ_i = A x_i):\n");
  for (Eigen::Index i = 0; i < lin.A.rows(); ++i) {
    for (Eigen::Index j = 0; j < lin.A.cols(); ++j) fmt::print(" {:>12.6g}", lin.A(i, j));
    fmt::print("\n");
  }
  fmt::print("\n{:>4} {:>22} {:>22} {:>12} {:>12} {:>10}  mode shape (largest entries)\n", "#",
             "Re λ [1/s]", "Im λ [1/s]", "f_n [Hz]", "f_d [Hz]", "ζ");
  int index = 0;
  for (const multibody::Mode& m : a.modes) {
    std::string shape;
    for (Eigen::Index i = 0; i < m.shape.size(); ++i) {
      if (std::abs(m.shape(i)) < 0.1) continue;
      shape += fmt::format(" {}:{:.3g}{:+.3g}i", lin.state_names[static_cast<std::size_t>(i)],
                           m.shape(i).real(), m.shape(i).imag());
    }
    fmt::print("{:>4} {:>22.14g} {:>22.14g} {:>12.6g} {:>12.6g} {:>10.4g} {}\n", ++index,
               m.eigenvalue.real(), m.eigenvalue.imag(), m.frequency_hz, m.damped_frequency_hz,
               m.damping_ratio, shape);
  }
}

void AddModesCommand(CLI::App& root) {
  auto opt = std::make_shared<ModesOptions>();
  CLI::App* cmd = root.add_subcommand(
      "modes", "Linearise a model (through its constraints) and print its eigenvalues, "
               "frequencies, damping ratios and mode shapes");
  cmd->add_option("model", opt->model, "model file or run configuration (YAML)")
      ->required()->check(RegularInputFile());
  cmd->add_option("--at", opt->at,
                  "operating point q=v1,...,vn and/or u=v1,...,vn (SI; default: the model's "
                  "initial state; dependent coordinates and speeds are solved)");
  cmd->add_option("--set", opt->set, "override a parameter, NAME=VALUE in SI (repeatable)");
  cmd->add_option("--time", opt->time, "time t [s] (default 0)")->check(FiniteNumber());
  cmd->add_flag("--json", opt->json,
                "print one JSON object {states, state_matrix, modes: [{real, imag, "
                "frequency_hz, damped_frequency_hz, damping_ratio, shape_real, shape_imag}]}");
  cmd->callback([opt] { RunModes(*opt); });
}

const CommandRegistration kRegistration{"modes", &AddModesCommand};

}  // namespace
}  // namespace hybridtest::app
