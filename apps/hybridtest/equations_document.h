#pragma once
// A model's equations as a document (symbolic/write_equations.h), from a model file, a run
// config or a built-in model's name: shared by `equations`, `compile-model` and `report
// --equations`.
#include <functional>
#include <string>

#include "hybridtest/models/catalogue.h"

namespace hybridtest::app {

struct EquationsOptions {
  std::string model;  // model file, run config (YAML) or built-in model name
  std::string format = "markdown";  // markdown | latex | sympy | c
  std::string out;
  bool overwrite = false;
  bool paper_form = false;
  bool numeric_parameters = false;
  int blades = 3;  // the built-in rotor's
};

// Rebuilds the model from other parameter values (symbolic/parameters.h).
using Rebuild = std::function<multibody::Model(const models::ParameterSet&)>;

// A model file (it has `coordinates:`), a run config, or a built-in model's name; *rebuild
// rebuilds it from other parameter values, starting from *declared (empty: the resolved ones).
// *source says where it came from. Throws ConfigError naming what is wrong.
models::BuiltModel LoadModel(const EquationsOptions& opt, std::string* source, Rebuild* rebuild,
                             models::ParameterSet* declared);

// The equations of opt.model in opt.format. Throws ConfigError for a bad format or model,
// ModelError for what the symbolic engine cannot derive.
std::string EquationsDocument(const EquationsOptions& opt);

// Throws ConfigError unless `format` is one `--format` takes: markdown, latex, sympy or c.
void CheckEquationsFormat(const std::string& format);

}  // namespace hybridtest::app
