// hybridtest models [NAME] [--blades N]
// Lists the built-in models with their coordinates, restoring-force slots and parameters
// (name, default value, unit, meaning): what a config's model section can say.
#include <fmt/core.h>

#include <cmath>

#include "command.h"
#include "hybridtest/models/catalogue.h"

namespace hybridtest::app {
namespace {

struct ModelsOptions {
  std::string name;
  int blades = 3;
};

void PrintModel(const std::string& name, int blades) {
  const models::BuiltModel built =
      models::BuildModel(name, blades, models::DefaultParameters(name, blades));
  const auto& model = built.model;
  fmt::print("{}: {}\n  coordinates:", name, built.description);
  for (const auto& q : model.coordinates()) fmt::print(" {} [{}]", q.name, q.unit);
  fmt::print("\n  speeds:     ");
  for (const auto& u : model.speeds()) fmt::print(" {} [{}]", u.name, u.unit);
  fmt::print("\n  restoring-force slots:");
  if (model.slots().empty()) fmt::print(" none");
  for (const auto& s : model.slots()) fmt::print(" {} ({})", s.info.name, s.info.description);
  fmt::print("\n  parameters (model.parameters in a config):\n");
  const models::ParameterSet defaults = models::DefaultParameters(name, blades);
  for (const auto& p : defaults.all()) {
    fmt::print("    {:<14} {:>12} {:<8} {}\n", p.name,
               std::isnan(p.value) ? std::string("inherit") : fmt::format("{:g}", p.value), p.unit,
               p.description);
  }
}

void AddModelsCommand(CLI::App& root) {
  auto opt = std::make_shared<ModelsOptions>();
  CLI::App* cmd = root.add_subcommand("models", "List the built-in models and their parameters");
  cmd->add_option("name", opt->name, "one model only");
  cmd->add_option("--blades", opt->blades, "number of rotor blades to show");
  cmd->callback([opt] {
    if (!opt->name.empty()) return PrintModel(opt->name, opt->blades);
    for (const auto& name : models::ModelNames()) PrintModel(name, opt->blades);
  });
}

const CommandRegistration kCommandModelsRegistration{"models", &AddModelsCommand};

}  // namespace
}  // namespace hybridtest::app
