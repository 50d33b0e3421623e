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
//   /metadata/config    string dataset: the config file's text ("" if unknown)
//   /metadata/sidecar   string dataset: the sidecar JSON ("null" if the run has none)
// Every channel dataset carries the string attributes `units`, `description` and `channel`
// (the CSV column name; a '/' in it becomes '_' in the dataset name). /metadata carries the
// attributes `format` ("hybridtest-hdf5/1"), `software_version` (of the exporter),
// `run_software_version` (from the sidecar, "" if unknown) and `source_csv`.
// Strings are variable-length UTF-8. Datasets are gzip-compressed when the filter exists.
#include <string>

#include "hybridtest/io/run_reader.h"

namespace hybridtest::report {

// Writes `run` to h5_path (created or truncated). Throws IoError naming the path and the
// HDF5 error if the file cannot be created or written.
void ExportHdf5(const io::RunData& run, const std::string& h5_path);

// HDF5 path of a channel's dataset in the layout above, e.g. "r1_force" → "/physical/r1/force".
std::string Hdf5DatasetPath(const std::string& channel_name);

}  // namespace hybridtest::report
