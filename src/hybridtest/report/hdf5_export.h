#pragma once
// ExportHdf5: a run (CSV + sidecar, read by io::LoadRun) as one self-describing HDF5 file.
//
// Layout (docs/results-format.md), one 1-D double dataset of length num_rows per channel:
//   /time/t
//   /coordinates/q1, q2, ...
//   /speeds/u1, u2, ...
//   /restoring_forces/r1, r2, ...
//   /physical/<slot>/command, position, force, lab_time   (from <slot>_command, ...)
//   /other/<name>                                         (every other channel)
//   /stages/<name>      the stage record <run>.stages.csv, one dataset per column (step,
//                       stage, t, <slot>_command, ...), when the run has one; the group's
//                       attribute source_csv names the file
//   /metadata/config    string dataset: the config file's text ("" if unknown)
//   /metadata/sidecar   string dataset: the sidecar JSON ("null" if the run has none)
// Every channel dataset carries the string attributes `units`, `description` and `channel`
// (the CSV column name; a '/' in it becomes '_' in the dataset name). /metadata carries the
// attributes `format` ("hybridtest-hdf5/1"), `software_version` (of the exporter),
// `run_software_version` (from the sidecar, "" if unknown) and `source_csv`.
// The root group carries the run's provenance as attributes: every key of the sidecar except
// its channel list, whatever keys the sidecar has (status, command, config_path, config,
// software_version, start_time, a test block, host, inputs with their sha256, ...), nested
// keys joined with '.' and array elements by index (test.specimen, extra.inputs.0.sha256);
// strings as strings, integers as int64, other numbers as double, an array of numbers as one
// 1-D double attribute, booleans as "true"/"false".
// Strings are variable-length UTF-8. Datasets are gzip-compressed when the filter exists.
#include <string>

#include "hybridtest/io/run_reader.h"

namespace hybridtest::report {

// Writes `run` to h5_path (created or truncated). Throws IoError naming the path and the
// HDF5 error if the file cannot be created or written.
// The writing is done by the module hybridtest_hdf5.so (hdf5_module.h, apps/hybridtest_hdf5/),
// the only code of hybridtest that links libhdf5, loaded here at the first export: it is found
// by FindModule (common/module_path.h: $HYBRIDTEST_HDF5_MODULE, beside the program, in
// <libdir>/hybridtest/ of the installed or configured prefix, in the build tree). Throws IoError
// naming the files looked for and how to build or reinstall it when it is missing, cannot be
// loaded or is of another interface version; nothing is written then.
void ExportHdf5(const io::RunData& run, const std::string& h5_path);

// HDF5 path of a channel's dataset in the layout above, e.g. "r1_force" → "/physical/r1/force".
std::string Hdf5DatasetPath(const std::string& channel_name);

}  // namespace hybridtest::report
