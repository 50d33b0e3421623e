#pragma once
// Results are never destroyed: the checks `run` and `simulate` make before a run writes
// anything (docs/results-format.md, "Never destroyed"; docs/decisions/0008-results-never-destroyed.md).
//
// A run writes up to four files: the journal <run>.csv, its sidecar <run>.meta.json, and for
// a hybrid test the stage record <run>.stages.csv with <run>.stages.meta.json. None of them may
// already exist unless the operator passes --overwrite; and none may be a file the run reads
// (its config, model file and tables, bench and token files: RunSpec::source.files), even
// with --overwrite.
#include <string>
#include <vector>

#include "hybridtest/io/run_input.h"

namespace hybridtest::io {

// "<dir>/<stem>.state.json" for the journal "<dir>/<stem>.csv": the run state (runner/run_state.h).
std::string RunStatePath(const std::string& csv_path);

// The files a run to csv_path may write, journal first.
std::vector<std::string> RunOutputFiles(const std::string& csv_path);

// The paths of `files` (RunSpec::source.files: what the compile read), for CheckRunOutputs.
std::vector<std::string> RunInputFiles(const std::vector<RunInput>& files);

// True if a and b name the same file: the same path once made absolute and normalized (./,
// .., symlinks of existing parts), or the same inode.
bool SameFile(const std::string& a, const std::string& b);

// Throws ConfigError if an output of a run to csv_path is one of `inputs` (always), is
// anything but a regular file where it exists (a device, a FIFO, a directory, a symlink:
// always, --overwrite never replaces those), or exists already and `overwrite` is false. The
// outputs checked are RunOutputFiles and the run state "<run>.state.json". The message names
// the file and how to fix it.
void CheckRunOutputs(const std::string& csv_path, const std::vector<std::string>& inputs,
                     bool overwrite);

}  // namespace hybridtest::io
