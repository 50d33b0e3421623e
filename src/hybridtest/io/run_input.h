#pragma once
// One file a run read, as the reader that opened it reports it (io/run_spec.h,
// SourceSpec::files): the compile fills the list while it reads, so that the run's record
// (io/run_inputs.h) and its output guards (io/run_outputs.h) name exactly what was read.
#include <string>

namespace hybridtest::io {

struct RunInput {
  // "config" (the run config), "model" (`model: {file: ...}`), "table" (a `csv:` table of the
  // model file), "bench" (a bench file: `transfer.config`, `plan --emulate`) or "token" (a
  // `token_file`: a secret, recorded by path only, never hashed or copied).
  std::string role;
  std::string path;  // as the reader opened it (relative paths resolved against their file)
};

}  // namespace hybridtest::io
