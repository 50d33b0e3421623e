#pragma once
// Parsing and checking of command-line values: numbers ("0.1,0.2,0.3", "nan" refused), input
// files (regular files only) and the runs the read-only commands take, with errors naming the
// option and exit status 2.
#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "hybridtest/io/run_reader.h"
#include "live_monitor.h"

namespace hybridtest::app {

// Splits a comma-separated list of finite numbers. Throws ConfigError naming `option`.
std::vector<double> ParseNumberList(const std::string& text, const std::string& option);

// CLI11 validators for numeric options that refuse what CLI11's own let through: NaN and
// infinities (CLI::NonNegativeNumber accepts "nan" and "inf"), and text after the number.
// The message names the option (CLI11 prefixes it) and the value. Exit status 2.
const CLI::Validator& FiniteNumber();
const CLI::Validator& PositiveFiniteNumber();
const CLI::Validator& NonNegativeFiniteNumber();
// A finite number in [min, max] (CLI::Range lets "nan" through).
CLI::Validator FiniteRange(double min, double max);

// An input file: it must exist and be a regular file (a FIFO would block the reader for ever,
// a device feed it without end, a directory is a slip). Replaces CLI::ExistingFile, which
// accepts FIFOs and devices. The message names the option and says what was found.
const CLI::Validator& RegularInputFile();

// The run (journal CSV and sidecar) that `report`, `compare`, `plot` and `export` read, given
// on the command line as `what` ("run", "--against"). A journal that is missing, not a
// regular file or not a journal is the user's input: ConfigError (exit 2) naming `what`,
// instead of an IoError (exit 1).
io::RunData LoadRunInput(const std::string& path, const std::string& what);

// Checks that `path` (given as `what`) is a regular file that starts with a journal's header
// line, "t,..." (monitor and resume read it piece by piece later; a file that is not a
// journal is refused now). Throws ConfigError naming `what`, the path and what was found.
void CheckJournalHeader(const std::string& path, const std::string& what);

// Checks the live-monitor options of `run` and `resume` that CLI11 cannot: --monitor-linger
// a finite number, and --token-file, --monitor-no-token and --monitor-linger only with
// --monitor (alone they would be ignored: an operator would believe a token guards the run).
// Throws ConfigError naming the option and the fix.
void CheckMonitorOptions(const MonitorCliOptions& options);

}  // namespace hybridtest::app
