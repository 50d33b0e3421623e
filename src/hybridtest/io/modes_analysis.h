#pragma once
// The front doors' one implementation of `modes` (`hybridtest modes` and Python's
// hybridtest.modes): load a model file or a run config, apply parameter overrides, take the
// operating point (the model's `initial:` state, a run config's `initial_state`, or the given
// q and/or u), optionally solve some coordinates for a steady state (multibody/
// steady_state.h), then linearise and take the modes (multibody/modes.h).
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "hybridtest/models/catalogue.h"
#include "hybridtest/multibody/modes.h"
#include "hybridtest/multibody/steady_state.h"

namespace hybridtest::io {

struct ModesRequest {
  std::string path;                                  // a model file or a run config (YAML)
  std::vector<std::pair<std::string, double>> set;   // parameter overrides (name, SI value)
  std::optional<std::vector<double>> q;              // (n) replaces the start's q [SI]
  std::optional<std::vector<double>> u;              // (n) replaces the start's u [SI]
  double time = 0.0;                                 // t of the operating point [s]
  std::vector<std::string> steady;                   // coordinates solved for u̇ = 0 (names)
  std::vector<std::string> driven;                   // speeds a drive holds (names; their
                                                     // rates are not required to vanish)
  multibody::SteadyStateOptions steady_options;      // tolerance, iterations (driven_speeds
                                                     // is filled from `driven`)
};

struct ModesReport {
  models::BuiltModel built;
  Eigen::VectorXd start;                             // the operating point asked for (2n + nz)
  std::optional<multibody::SteadyState> steady;      // when `steady` named coordinates
  multibody::ModeAnalysis analysis;                  // at the (steady, assembled) point
};

// The model (overrides applied) and the operating point before assembly, in *x0. Throws
// ConfigError for a file that is neither a model file nor a run config, an unknown parameter,
// --set on a config that names a built-in model, or q/u of the wrong length.
models::BuiltModel LoadModesModel(const ModesRequest& request, Eigen::VectorXd* x0);

// Indices of the named quantities in `known` (the model's coordinates or speeds; `kind` is
// "coordinate" or "speed"); ConfigError naming an unknown one and the known ones.
std::vector<int> QuantityIndices(const std::vector<multibody::QuantityInfo>& known,
                                 const std::vector<std::string>& names, const std::string& kind,
                                 const std::string& where);

// The whole analysis. A model that cannot be evaluated or assembled at the operating point,
// and a steady state that is not found (its message: the residual, the largest speed rate,
// what to try), are ModelErrors naming the file ("modes PATH: at the operating point: ...");
// the command line turns them into exit status 2 (the user's input), Python into ModelError.
ModesReport AnalyseModes(const ModesRequest& request);

}  // namespace hybridtest::io
