#pragma once
// The one reader of files a user names as input: run configs, model files, bench files,
// campaign tables, token files, and the journals that `report`, `compare`, `plot`, `monitor`
// and `resume` read. A path that names a FIFO, a device, a socket or a directory is refused
// before anything is read from it (a FIFO opened for reading would block for ever; a device
// could feed an endless stream), and a file larger than the caller's bound is refused before
// it fills memory. Every refusal is a ConfigError (exit status 2 in the CLI) that names the
// input, the path, what was found and how to fix it, e.g.
//   --config = 'bench.yaml': not a regular file (a FIFO); give a bench file (YAML) here
//   --token-file = 'tok': cannot open this token file (no such file); check that it exists ...
#include <cstddef>
#include <string>
#include <string_view>

namespace hybridtest {

// Why `path` cannot be read as an input file: "" when it is a regular file (symbolic links
// are followed), else "no such file", "a FIFO", "a directory", "a device", "a socket" or the
// system's reason. Never opens the file; never blocks.
std::string RegularFileProblem(const std::string& path);

// Throws ConfigError "<what> = '<path>': not a regular file (<problem>); give a <expected>
// here" (or "cannot open this <expected> (no such file)...") unless RegularFileProblem(path)
// is empty. `what` names the input as the user gave it (an option such as "--token-file", a
// key path such as "campaign.yaml: table"; empty: the message starts with the path);
// `expected` is a noun phrase for the file wanted, without article ("run journal (CSV)").
void RequireRegularFile(const std::string& path, std::string_view what,
                        std::string_view expected);

// The whole content of the regular file `path`, at most `max_bytes` bytes. The file is opened
// without blocking (O_NONBLOCK) and checked to be a regular file on the open descriptor
// before any read, so a FIFO swapped in after a check cannot hang the reader either. Throws
// ConfigError (as RequireRegularFile) when it is missing, not a regular file, unreadable or
// larger than `max_bytes` (Unit: [bytes]).
std::string ReadInputFile(const std::string& path, std::string_view what,
                          std::string_view expected, std::size_t max_bytes);

}  // namespace hybridtest
