#pragma once
// OutputGuard: no command writes over a file it reads, over a file of a run it reads, or onto
// a device or a FIFO (docs/results-format.md, "Never destroyed"). One check for every command
// that writes a derived file: `report --out`, `export --csv/--hdf5`, `plot --out`,
// `compare --out` (`run`/`simulate` check their own outputs with CheckRunOutputs, which uses
// the same protected-file list for the run it writes).
//
// Files are compared by identity (device and inode, std::filesystem::equivalent) and, for
// files that do not exist yet, by their normalized absolute path with symlinks of existing
// parts resolved: a symlink to the journal is the journal. The type of an output that exists
// is read with stat() before anything opens it, so a FIFO or a device is refused without
// blocking.
#include <string>
#include <vector>

namespace hybridtest::io {

// One file that must survive a command: its path and what it is, for the message ("the
// journal of results/run.csv", "the config of results/run.csv", "run A").
struct ProtectedFile {
  std::string path;
  std::string role;
};

// The files of the run whose journal is csv_path that exist or may exist: the journal, its
// sidecar, its stage record and that record's sidecar, its run state, its lock, the staged
// ("<file>.partial") copies; and the files the run read, as its sidecar or its run state
// records them (config, model, bench, token; paths relative to the journal's directory).
// Best effort: a missing or unreadable sidecar or state adds nothing.
std::vector<ProtectedFile> RunProtectedFiles(const std::string& csv_path,
                                             const std::string& label = "");

// Throws ConfigError (exit 2) if the file `out`, which the command is about to write (given
// by `option`, e.g. "--out"), is one of `inputs` (or a symlink or hard link to one), or exists
// and is not a regular file (a FIFO, a device, a directory, a socket). The message names the
// option, the path, the file it would destroy, and the fix. Nothing is opened.
void CheckOutputFile(const std::string& out, const std::vector<ProtectedFile>& inputs,
                     const std::string& option);

// The same for a directory a command writes into (`plot --out DIR`, `compare --out DIR`):
// refused if `dir` exists and is not a directory, is itself an input, or holds an input whose
// name the command may write (`written_names`: exact file names such as "comparison.csv";
// `written_extensions`: ".png", ".svg").
void CheckOutputDirectory(const std::string& dir, const std::vector<ProtectedFile>& inputs,
                          const std::string& option,
                          const std::vector<std::string>& written_names,
                          const std::vector<std::string>& written_extensions);

}  // namespace hybridtest::io
