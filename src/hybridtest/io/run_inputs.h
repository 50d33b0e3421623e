#pragma once
// The record of the files a run read, so that `resume` continues with exactly those files,
// found from the run itself and never from the current directory (docs/safety.md, "Resuming
// a run"). The files are the ones the compile reported while it read them
// (RunSpec::source.files, io/run_input.h): the config, the model file and its `csv:` tables,
// bench files and token files. Each entry: {"role", "path", "sha256"}; `path` is relative to
// the journal's directory (absolute if the two share no root); `sha256` is the digest of the
// content the run read (for the config: the text the spec was compiled from); a token file
// (a secret) has neither digest nor copy, only its path.
#include <nlohmann/json.hpp>

#include <string>
#include <string_view>
#include <vector>

#include "hybridtest/io/run_input.h"
#include "hybridtest/io/run_spec.h"

namespace hybridtest::io {

// One input file, read once for its record and the provenance.
struct InputText {
  RunInput file;
  std::string text;    // the content ("" for a token: never read here)
  std::string sha256;  // of the content ("" for a token)
};

// Every file of spec.source.files, in order: the config's text is spec.source.config_text (what
// the spec was compiled from), every other file but a token is read whole. Throws IoError
// naming a file that cannot be read.
std::vector<InputText> ReadInputTexts(const RunSpec& spec);

// The record for a run whose journal is csv_path: [{role, path, sha256}] (no sha256 for a
// token).
nlohmann::json RecordRunInputs(const std::vector<InputText>& inputs, const std::string& csv_path);

// Every input but a token, verbatim: [{role, path (as the reader opened it), sha256, text}] —
// the sidecar's provenance.
nlohmann::json InputTexts(const std::vector<InputText>& inputs);

// The run config's path from the record, resolved against the journal's directory. Throws
// ConfigError if the record has no config entry.
std::string RecordedConfigPath(const nlohmann::json& inputs, const std::string& csv_path);

// Throws ConfigError (exit 2) naming every file the resumed run `spec` read (its compile's
// source.files) that differs from the record: missing, changed (both digests), or not the same
// list of files. `rule` and `fix` word the message for another reader than resume.
void CheckRunInputs(const nlohmann::json& recorded, const RunSpec& spec,
                    const std::string& csv_path,
                    std::string_view rule = "resume continues a run only with the files it "
                                            "started with",
                    std::string_view fix = "Restore those files, or start a new run with "
                                           "hybridtest run --out NEW.csv");

}  // namespace hybridtest::io
