#pragma once
// The record of the files a run reads, so that `resume` continues with exactly those files,
// found from the run itself and never from the current directory (docs/safety.md, "Resuming
// a run"). Each entry: {"role", "path", "sha256"}; `path` is relative to the journal's
// directory (absolute if the two share no root); `sha256` is the digest of the content the run
// read (for the config: the text kept in the sidecar); a token file (a secret) has no digest.
#include <nlohmann/json.hpp>

#include <string>

#include "hybridtest/io/config.h"

namespace hybridtest::io {

// The record for a run of `cfg` whose journal is csv_path. Throws IoError naming a file that
// cannot be read.
nlohmann::json RecordRunInputs(const SimulationConfig& cfg, const std::string& csv_path);

// The run config's path from the record, resolved against the journal's directory. Throws
// ConfigError if the record has no config entry.
// Every input of cfg but a token file, verbatim: [{role, path (as the config resolves it),
// sha256, text}] — the sidecar's provenance.
nlohmann::json InputTexts(const SimulationConfig& cfg);

std::string RecordedConfigPath(const nlohmann::json& inputs, const std::string& csv_path);

// Throws ConfigError (exit 2) naming every file of the resumed run `cfg` that differs from the
// record: missing, changed (both digests), or not the same list of files.
void CheckRunInputs(const nlohmann::json& recorded, const SimulationConfig& cfg,
                    const std::string& csv_path);

}  // namespace hybridtest::io
