#pragma once
// Results are never destroyed: the checks `run` and `simulate` make before a run writes
// anything (docs/results-format.md, "Never destroyed"; docs/decisions/0008-results-never-destroyed.md).
//
// A run writes up to four files: the journal <run>.csv, its sidecar <run>.meta.json, and for
// a hybrid test the stage record <run>.stages.csv with <run>.stages.meta.json. None of them may
// already exist unless the operator passes --overwrite; and none may be a file the run reads
// (its config, the bench files the config names), even with --overwrite.
#include <string>
#include <vector>

#include "hybridtest/io/config.h"

namespace hybridtest::io {

// The files a run to csv_path may write, journal first.
std::vector<std::string> RunOutputFiles(const std::string& csv_path);

// The files a run of `cfg` reads: the config itself and every `transfer.config` bench file of
// its substructures (relative to the config's directory).
std::vector<std::string> RunInputFiles(const SimulationConfig& cfg);

// True if a and b name the same file: the same path once made absolute and normalized (./,
// .., symlinks of existing parts), or the same inode.
bool SameFile(const std::string& a, const std::string& b);

// Throws ConfigError if an output of a run to csv_path is one of `inputs` (always), or exists
// already and `overwrite` is false. The message names the file and how to fix it.
void CheckRunOutputs(const std::string& csv_path, const std::vector<std::string>& inputs,
                     bool overwrite);

}  // namespace hybridtest::io
