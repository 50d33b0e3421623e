// hybridtest eom CONFIG --time T --state x1,...,x2n [--restoring r1,...] [--json]
// Evaluates the equations of motion of the configured model once: M u̇ = forcing, ẋ.
#include <fmt/core.h>

#include <iostream>
#include <nlohmann/json.hpp>

#include "cli_values.h"
#include "command.h"
#include "hybridtest/common/error.h"
#include "hybridtest/io/config.h"
#include "hybridtest/multibody/assembly.h"
#include "hybridtest/multibody/constraints.h"
#include "hybridtest/multibody/kane.h"
#include "hybridtest/io/substructure_config.h"

namespace hybridtest::app {
namespace {

struct EomOptions {
  std::string config;
  double time = 0.0;
  std::string state;
  std::string restoring;
  bool json = false;
  bool assemble = false;
};

void RunEom(const EomOptions& opt) {
  const io::SimulationConfig cfg = io::LoadSimulationConfig(opt.config);
  const multibody::Model& model = cfg.model.model;
  const int n = model.num_coordinates();
  const int nx = model.num_states();
  const std::vector<double> xs = ParseNumberList(opt.state, "--state");
  if (static_cast<int>(xs.size()) != nx) {
    throw ConfigError(fmt::format("--state has {} values; the {} model needs {} (x = [q; u{}] "
                                  "with n = {}{})", xs.size(), cfg.model.name, nx,
                                  nx > 2 * n ? "; z" : "", n,
                                  nx > 2 * n ? fmt::format(" and {} extra states", nx - 2 * n) : ""));
  }
  Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(xs.data(), nx);
  if (opt.assemble && model.has_constraints()) {
    try {
      x = multibody::AssembleState(model, opt.time, x).x;
    } catch (const ModelError& e) {
      throw ConfigError(fmt::format("--state: {}", e.what()));
    }
  }
  multibody::Data<double> data(model);
  Eigen::VectorXd r(model.num_slots());
  if (!opt.restoring.empty()) {
    const std::vector<double> rs = ParseNumberList(opt.restoring, "--restoring");
    if (static_cast<int>(rs.size()) != model.num_slots()) {
      throw ConfigError(fmt::format("--restoring has {} values; the model has {} restoring-force "
                                    "slots", rs.size(), model.num_slots()));
    }
    r = Eigen::Map<const Eigen::VectorXd>(rs.data(), model.num_slots());
  } else {
    // The configured (numerical) substructures compute r^s from the slot displacements.
    const auto subs = io::MakeSubstructures(
        cfg, {std::nullopt, false, "give its restoring force with --restoring r1,...,rm",
              std::nullopt, nullptr});
    Eigen::VectorXd d(model.num_slots());
    multibody::CalcSlotDisplacements<double>(model, data, opt.time, x.head(n), d);
    for (int s = 0; s < model.num_slots(); ++s) {
      subs[s]->Trial({&d(s), 1}, {&r(s), 1}, {0, 0, opt.time});
    }
  }
  Eigen::VectorXd xdot(nx);
  multibody::CalcStateDerivative<double>(model, data, opt.time, x, r, xdot);
  // A constrained model: the reduced equations [Cᵀ M; B] u̇ = [Cᵀ g; −bias], unstabilised
  // (constraints.h), in the speeds' order, rows: independent speeds, then constraint rows.
  const bool constrained = model.has_constraints();
  if (constrained) multibody::CalcReducedEquations(model, data, false);

  if (opt.json) {
    nlohmann::json out;
    out["mass_matrix"] = nlohmann::json::array();
    for (int i = 0; i < n; ++i) {
      std::vector<double> row;
      for (int j = 0; j < n; ++j) row.push_back(data.M(i, j));
      out["mass_matrix"].push_back(row);
    }
    out["forcing"] = std::vector<double>(data.g.data(), data.g.data() + n);
    out["xdot"] = std::vector<double>(xdot.data(), xdot.data() + nx);
    out["restoring"] = std::vector<double>(r.data(), r.data() + r.size());
    if (constrained) {
      out["state"] = std::vector<double>(x.data(), x.data() + nx);
      out["reduced_mass_matrix"] = nlohmann::json::array();
      for (int i = 0; i < n; ++i) {
        std::vector<double> row;
        for (int j = 0; j < n; ++j) row.push_back(data.reduced_M(i, j));
        out["reduced_mass_matrix"].push_back(row);
      }
      out["reduced_forcing"] = std::vector<double>(data.reduced_f.data(), data.reduced_f.data() + n);
      out["dependent_speeds"] = data.dependent;
      out["constraint_velocity"] = std::vector<double>(
          data.constraint_velocity.data(), data.constraint_velocity.data() + data.constraint_velocity.size());
      out["constraint_position"] = std::vector<double>(
          data.constraint_position.data(), data.constraint_position.data() + data.constraint_position.size());
    }
    std::cout << out.dump() << "\n";
    return;
  }
  fmt::print("model {} at t = {} s (convention M u̇ = f, x = [q; u])\n", cfg.model.name,
             opt.time);
  fmt::print("mass matrix M:\n");
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) fmt::print(" {:>24.17g}", data.M(i, j));
    fmt::print("\n");
  }
  fmt::print("right-hand side f (the forcing):\n");
  for (int i = 0; i < n; ++i) fmt::print(" {:>24.17g}", data.g(i));
  // Each slot with its name and unit: a moment slot is in N·m, not N.
  fmt::print("\nrestoring forces r^s:\n");
  for (int i = 0; i < r.size(); ++i) {
    const auto& info = model.slots()[static_cast<std::size_t>(i)].info;
    fmt::print(" {:>24.17g} [{}] {}\n", r(i), info.unit.empty() ? "N" : info.unit, info.name);
  }
  if (constrained) {
    fmt::print("reduced equations [Cᵀ M; B] u̇ = [Cᵀ f; −(Ḃu + ċ)] (dependent speeds:");
    for (int j : data.dependent) fmt::print(" {}", model.speeds()[j].name);
    fmt::print("):\n");
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) fmt::print(" {:>24.17g}", data.reduced_M(i, j));
      fmt::print(" | {:>24.17g}\n", data.reduced_f(i));
    }
  }
  fmt::print("xdot:\n");
  for (int i = 0; i < nx; ++i) fmt::print(" {:>24.17g}", xdot(i));
  fmt::print("\n");
}

void AddEomCommand(CLI::App& root) {
  auto opt = std::make_shared<EomOptions>();
  CLI::App* cmd = root.add_subcommand(
      "eom", "Evaluate the equations of motion M u̇ = forcing once, at a given time and state");
  cmd->add_option("config", opt->config, "run configuration (YAML)")->required();
  cmd->add_option("--time", opt->time, "time t [s]")->required()->check(FiniteNumber());
  cmd->add_option("--state", opt->state, "x = [q; u], 2n comma-separated SI values")->required();
  cmd->add_option("--restoring", opt->restoring,
                  "static restoring forces r^s, one per slot, each in its slot's unit (N, or "
                  "N·m for a moment slot; default: computed by the configured numerical "
                  "substructures)");
  cmd->add_flag("--json", opt->json, "print one JSON object {mass_matrix, forcing, xdot} (a "
                "constrained model adds state, reduced_mass_matrix, reduced_forcing, "
                "dependent_speeds, constraint_velocity, constraint_position)");
  cmd->add_flag("--assemble", opt->assemble,
                "a constrained model: solve the dependent coordinates and speeds of --state "
                "from the independent ones first");
  cmd->callback([opt] { RunEom(*opt); });
}

const CommandRegistration kCommandEomRegistration{"eom", &AddEomCommand};

}  // namespace
}  // namespace hybridtest::app
