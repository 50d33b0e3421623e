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

// How a mode reads (one per ModeAnalysis::modes, same order). The coordinates read are the
// model file's `modes.coordinates` (modelfile/model_file_modes.h), else every independent
// coordinate; the mode's shape is normalised so that the largest of them is 1 (lean, not the
// rear contact's drift, for the bicycle's capsize).
struct ModeReadout {
  std::string label;                  // the first matching `modes.labels` entry; empty: none
  std::vector<std::string> dominant;  // read coordinates with |shape| ≥ ½ the largest, largest
                                      // first (empty for λ = 0)
  bool unstable = false;              // Re λ > kModeTolerance · max(1, max |λ|)
};

// Relative size below which Re λ, Im λ or |λ| count as zero (of max(1, max |λ|) [1/s]).
inline constexpr double kModeTolerance = 1e-9;
// Largest max |u̇| [the speed rates' units] at which the operating point counts as steady.
inline constexpr double kEquilibriumTolerance = 1e-8;

struct ModesReport {
  models::BuiltModel built;
  Eigen::VectorXd start;                             // the operating point asked for (2n + nz)
  std::optional<multibody::SteadyState> steady;      // when `steady` named coordinates
  multibody::ModeAnalysis analysis;                  // at the (steady, assembled) point
  std::vector<ModeReadout> readouts;                 // one per analysis.modes
  // max |u̇| at the operating point (every speed): above kEquilibriumTolerance the point is
  // not an equilibrium and the modes describe only the instantaneous linearisation (the
  // fronts warn and suggest --steady / steady=). Not computed with `steady` (it has its own).
  multibody::SpeedRateResidual residual;
  bool equilibrium = true;
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
