// hybridtest modes MODEL_OR_CONFIG [--at q=...,u=...] [--set NAME=VALUE ...] [--time T]
//                 [--steady NAMES] [--json]
// Linearises the model about an operating point (through its constraints: the state matrix
// in the independent states) and prints the eigenvalues, natural and damped frequencies,
// damping ratios and mode shapes (multibody/modes.h). The operating point is the model's
// initial state (a model file's `initial:` values, or a run config's initial_state),
// assembled, unless --at gives q and/or u; --steady first solves the named coordinates for
// u̇ = 0 (multibody/steady_state.h). The loading and the analysis are io::AnalyseModes, shared
// with Python's hybridtest.modes.
#include <fmt/core.h>

#include <iostream>
#include <sstream>
#include <nlohmann/json.hpp>

#include "cli_values.h"
#include "command.h"
#include "hybridtest/common/error.h"
#include "hybridtest/io/modes_analysis.h"

namespace hybridtest::app {
namespace {

struct ModesOptions {
  std::string model;
  std::string at;
  std::vector<std::string> set;
  double time = 0.0;
  std::string steady;
  std::string driven;
  multibody::SteadyStateOptions steady_options;
  bool json = false;
};

// --at q=a,b,...,u=c,d,...: either part may be left out (the lengths are checked by
// io::LoadModesModel).
void ParseAt(const std::string& at, io::ModesRequest& request) {
  if (at.empty()) return;
  std::vector<double>* target = nullptr;
  std::string token;
  std::stringstream ss(at);
  while (std::getline(ss, token, ',')) {
    if (token.rfind("q=", 0) == 0 || token.rfind("u=", 0) == 0) {
      auto& part = token[0] == 'q' ? request.q : request.u;
      part.emplace();
      target = &*part;
      token = token.substr(2);
    }
    if (target == nullptr) {
      throw ConfigError(fmt::format("--at {}: expected q=v1,...,vn and/or u=v1,...,vn", at));
    }
    target->push_back(ParseNumberList(token, "--at")[0]);
  }
}

io::ModesRequest MakeRequest(const ModesOptions& opt) {
  io::ModesRequest request;
  request.path = opt.model;
  request.time = opt.time;
  request.steady_options = opt.steady_options;
  for (const std::string& item : opt.set) {
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos) {
      throw ConfigError(fmt::format("--set {}: expected NAME=VALUE (a parameter, SI)", item));
    }
    const std::vector<double> v = ParseNumberList(item.substr(eq + 1), "--set " + item);
    if (v.size() != 1) throw ConfigError(fmt::format("--set {}: expected one number", item));
    request.set.emplace_back(item.substr(0, eq), v[0]);
  }
  ParseAt(opt.at, request);
  for (auto [text, names] : {std::pair{&opt.steady, &request.steady},
                             std::pair{&opt.driven, &request.driven}}) {
    std::string name;
    std::stringstream ss(*text);
    while (std::getline(ss, name, ',')) {
      if (!name.empty()) names->push_back(name);
    }
  }
  return request;
}

nlohmann::json SteadyJson(const multibody::Model& model, const multibody::SteadyState& s) {
  nlohmann::json j;
  j["coordinates"] = nlohmann::json::array();
  j["values"] = nlohmann::json::array();
  for (int k : s.free_coordinates) {
    j["coordinates"].push_back(model.coordinates()[static_cast<std::size_t>(k)].name);
    j["values"].push_back(s.x(k));
  }
  j["iterations"] = s.iterations;
  j["residual"] = s.residual;
  j["residual_speed"] = model.speeds()[static_cast<std::size_t>(s.worst_speed)].name;
  j["residual_unit"] = multibody::SpeedRateUnit(model, s.worst_speed);
  j["converged"] = s.converged;
  j["driven"] = nlohmann::json::array();
  for (int k : s.driven_speeds) {
    j["driven"].push_back(model.speeds()[static_cast<std::size_t>(k)].name);
  }
  return j;
}

void RunModes(const ModesOptions& opt) {
  const io::ModesReport report = [&] {
    try {
      return io::AnalyseModes(MakeRequest(opt));
    } catch (const ModelError& e) {
      throw ConfigError(e.what());  // the operating point is the user's input: exit 2
    }
  }();
  const models::BuiltModel& built = report.built;
  const multibody::ModeAnalysis& a = report.analysis;
  const auto& lin = a.linearization;
  if (opt.json) {
    nlohmann::json out;
    out["model"] = built.name;
    out["states"] = lin.state_names;
    out["operating_point"] = std::vector<double>(a.x.data(), a.x.data() + a.x.size());
    if (report.steady) out["steady"] = SteadyJson(built.model, *report.steady);
    out["state_matrix"] = nlohmann::json::array();
    for (Eigen::Index i = 0; i < lin.A.rows(); ++i) {
      std::vector<double> row(lin.A.cols());
      for (Eigen::Index j = 0; j < lin.A.cols(); ++j) row[static_cast<std::size_t>(j)] = lin.A(i, j);
      out["state_matrix"].push_back(row);
    }
    out["equilibrium"] = report.equilibrium;
    if (!report.steady && report.residual.worst_speed >= 0) {
      out["residual"] = report.residual.residual;
      out["residual_speed"] = built.model.speeds()[static_cast<std::size_t>(
          report.residual.worst_speed)].name;
    }
    out["modes"] = nlohmann::json::array();
    for (std::size_t k = 0; k < a.modes.size(); ++k) {
      const multibody::Mode& m = a.modes[k];
      nlohmann::json j;
      j["label"] = report.readouts[k].label;
      j["dominant"] = report.readouts[k].dominant;
      j["unstable"] = report.readouts[k].unstable;
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
  fmt::print("]\n");
  if (!report.equilibrium) {
    const int k = report.residual.worst_speed;
    fmt::print("warning: not an equilibrium: max |u̇| = {:.3g} {} (u̇ of {}), so these modes "
               "describe the linearisation at this instant only, not motions about a steady "
               "state; to find one, name the coordinates to solve for with --steady (and the "
               "speeds a drive holds with --driven)\n", report.residual.residual,
               multibody::SpeedRateUnit(built.model, k),
               built.model.speeds()[static_cast<std::size_t>(k)].name);
  }
  if (report.steady) {
    const multibody::SteadyState& st = *report.steady;
    fmt::print("steady state (u̇ = 0) in {} iteration(s), residual max |u̇| = {:.3g} {} (u̇ of "
               "{}):", st.iterations, st.residual,
               multibody::SpeedRateUnit(built.model, st.worst_speed),
               built.model.speeds()[static_cast<std::size_t>(st.worst_speed)].name);
    for (int k : st.free_coordinates) {
      const auto& c = built.model.coordinates()[static_cast<std::size_t>(k)];
      fmt::print(" {} = {:.15g} {}", c.name, st.x(k), c.unit);
    }
    fmt::print("\n");
  }
  fmt::print("independent states ({}):", lin.state_names.size());
  for (const std::string& s : lin.state_names) fmt::print(" {}", s);
  fmt::print("\nstate matrix A (ẋ_i = A x_i):\n");
  for (Eigen::Index i = 0; i < lin.A.rows(); ++i) {
    for (Eigen::Index j = 0; j < lin.A.cols(); ++j) fmt::print(" {:>12.6g}", lin.A(i, j));
    fmt::print("\n");
  }
  fmt::print("\n{:>4} {:>22} {:>22} {:>12} {:>12} {:>10}  {:<8} {:<20} mode shape (largest "
             "entries)\n", "#", "Re λ [1/s]", "Im λ [1/s]", "f_n [Hz]", "f_d [Hz]", "ζ",
             "stable?", "mode");
  int index = 0;
  int unstable = 0;
  for (std::size_t k = 0; k < a.modes.size(); ++k) {
    const multibody::Mode& m = a.modes[k];
    const io::ModeReadout& r = report.readouts[k];
    unstable += r.unstable ? 1 : 0;
    std::string name = r.label;
    if (!r.dominant.empty()) {
      std::string coords;
      for (const std::string& c : r.dominant) coords += (coords.empty() ? "" : "+") + c;
      name = name.empty() ? coords : fmt::format("{} ({})", name, coords);
    }
    if (name.empty()) name = "-";
    std::string shape;
    for (Eigen::Index i = 0; i < m.shape.size(); ++i) {
      if (std::abs(m.shape(i)) < 0.1) continue;
      shape += fmt::format(" {}:{:.3g}{:+.3g}i", lin.state_names[static_cast<std::size_t>(i)],
                           m.shape(i).real(), m.shape(i).imag());
    }
    fmt::print("{:>4} {:>22.14g} {:>22.14g} {:>12.6g} {:>12.6g} {:>10.4g}  {:<8} {:<20}{}\n",
               ++index, m.eigenvalue.real(), m.eigenvalue.imag(), m.frequency_hz,
               m.damped_frequency_hz, m.damping_ratio, r.unstable ? "UNSTABLE" : "stable", name,
               shape);
  }
  if (unstable > 0) {
    fmt::print("{} unstable mode(s): Re λ > 0, the motion grows as e^(Re λ t)\n", unstable);
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
  cmd->add_option("--steady", opt->steady,
                  "coordinates to solve first for a steady state u̇ = 0, comma separated "
                  "(q1,q3), with the other coordinates and the independent speeds held");
  cmd->add_option("--driven", opt->driven,
                  "with --steady: speeds a drive holds at their values (a motor at its set "
                  "speed), comma separated; their rates need not vanish");
  cmd->add_option("--steady-tolerance", opt->steady_options.tolerance,
                  "steady state: largest |u̇| accepted, in the speed rates' units (default "
                  "1e-10)")->check(CLI::PositiveNumber);
  cmd->add_option("--steady-iterations", opt->steady_options.max_iterations,
                  "steady state: most Gauss–Newton iterations (default 50)")
      ->check(CLI::Range(1, multibody::kMaxSteadyIterations));
  cmd->add_flag("--json", opt->json,
                "print one JSON object {model, states, operating_point, state_matrix, "
                "equilibrium, residual, residual_speed, modes: [{real, imag, frequency_hz, "
                "damped_frequency_hz, damping_ratio, label, dominant, unstable, shape_real, "
                "shape_imag}], steady: {coordinates, values, iterations, residual, "
                "residual_speed, residual_unit, converged, driven} (with --steady)}");
  cmd->callback([opt] { RunModes(*opt); });
}

const CommandRegistration kCommandModesRegistration{"modes", &AddModesCommand};

}  // namespace
}  // namespace hybridtest::app
