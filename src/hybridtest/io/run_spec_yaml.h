#pragma once
// Compiles a run config (YAML; io/config.h shows its keys) with its bench and model files into
// a RunSpec, once: every file is read and every key checked here, with errors that name
// file:line, the key path and the fix. Nothing downstream reads YAML again.
#include <string>

#include "hybridtest/io/config.h"
#include "hybridtest/io/run_spec.h"
#include "hybridtest/io/substructure_config.h"

namespace hybridtest::io {

// The spec of the config file at `path`. The output path is the config's output.csv, else
// results/<config name>.csv (callers override spec.output). Throws ConfigError.
RunSpec LoadRunSpec(const std::string& path, const SubstructureOptions& options = {});
// The same from a parsed config (the caller keeps `cfg` for the run guards of io/run_inputs.h).
RunSpec CompileRunSpec(const SimulationConfig& cfg, const SubstructureOptions& options = {});

}  // namespace hybridtest::io
