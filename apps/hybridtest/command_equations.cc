// hybridtest equations MODEL_OR_CONFIG [--format markdown|latex|sympy|c] [--out FILE]
//                      [--overwrite] [--paper-form] [--blades N]
// hybridtest compile-model MODEL_OR_CONFIG [--blades N]
// Prints a model's equations of motion symbolically, derived by the engine itself on the
// Symbolic scalar, or as C; compiles that C into the cache (docs/equations.md, decision 0019).
#include <fmt/core.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

#include "command.h"
#include "equations_document.h"
#include "hybridtest/common/error.h"
#include "hybridtest/io/output_guard.h"
#include "hybridtest/symbolic/compiled_model.h"

namespace hybridtest::app {
namespace {

// The MODEL_OR_CONFIG argument and --blades, as both subcommands take them.
void AddModelArguments(CLI::App* cmd, EquationsOptions& opt) {
  cmd->add_option("model", opt.model,
                  "model file, run config (YAML) or built-in model name (rotor, ...)")
      ->required();
  cmd->add_option("--blades", opt.blades, "blade count of the built-in rotor (default 3)");
}

void RunEquations(const EquationsOptions& opt) {
  CheckEquationsFormat(opt.format);  // a bad format before any work
  if (!opt.out.empty()) {
    io::CheckOutputFile(opt.out, {{opt.model, "the model"}}, "--out");
    std::error_code ec;
    if (std::filesystem::exists(opt.out, ec) && !opt.overwrite) {
      throw ConfigError(fmt::format("--out {}: the file exists; give --overwrite to replace it, "
                                    "or another path", opt.out));
    }
  }
  const std::string text = EquationsDocument(opt);
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
  AddModelArguments(cmd, *opt);
  cmd->add_option("--format", opt->format,
                  "markdown (default), latex, sympy, or c (the right-hand side as one C function)");
  cmd->add_option("--out", opt->out, "write to this file instead of standard output");
  cmd->add_flag("--overwrite", opt->overwrite, "replace an existing --out file");
  cmd->add_flag("--paper-form", opt->paper_form,
                "also print the paper's form M_p ẋ + g_p = 0 (Eq. 18)");
  cmd->add_flag("--numeric-parameters", opt->numeric_parameters,
                "print the parameters' values instead of their symbols (skips the rebuilds "
                "that recover the symbols)");
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
  AddModelArguments(cmd, *opt);
  cmd->callback([opt] { RunCompileModel(*opt); });
}

const CommandRegistration kCommandEquationsRegistration{"equations", &AddEquationsCommand};
const CommandRegistration kCompileRegistration{"compile-model", &AddCompileModelCommand};

}  // namespace
}  // namespace hybridtest::app
