#pragma once
/* The C interface between report::ExportHdf5 (hdf5_export.cc) and the HDF5 writer module
 * hybridtest_hdf5.so (apps/hybridtest_hdf5/), which alone links libhdf5: the hybridtest binary
 * and the layer libraries do not, so that no command but an HDF5 export pays for loading
 * libhdf5 and the libraries it needs (libcurl, TLS, Kerberos, LDAP: about half the binary's
 * shared libraries and 17 ms of every start).
 *
 * ExportHdf5 does everything but the writing: it maps channels to dataset paths, reads the
 * stage record, flattens the sidecar into attributes and fills a hybridtest_hdf5_run; the
 * module writes it in the layout of hdf5_export.h. Plain C types only, no exception crosses
 * the boundary: the entry point returns 0, or nonzero with the reason in `error`.
 *
 * The entry point's name carries the version of this interface; a change to any struct here
 * gets a new version (and name), so that a stale module is refused by dlsym, not misread. */
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define HYBRIDTEST_HDF5_MODULE_FILE "hybridtest_hdf5.so"
#define HYBRIDTEST_HDF5_ENTRY_POINT "hybridtest_hdf5_write_v1"

/* One 1-D double dataset of `rows` values (rows from the table it is in). */
typedef struct {
  const char* path;        /* absolute HDF5 path, e.g. "/physical/r1/force" */
  const char* channel;     /* the CSV column name: attribute `channel` */
  const char* units;       /* attribute `units` */
  const char* description; /* attribute `description` */
  const double* values;    /* rows values, contiguous */
} hybridtest_hdf5_dataset;

typedef enum {
  HYBRIDTEST_HDF5_STRING = 0, /* text: a variable-length UTF-8 string */
  HYBRIDTEST_HDF5_INT64 = 1,  /* integer: a scalar int64 */
  HYBRIDTEST_HDF5_DOUBLE = 2, /* numbers[0]: a scalar double */
  HYBRIDTEST_HDF5_DOUBLES = 3 /* numbers[0..count): a 1-D double array */
} hybridtest_hdf5_kind;

/* One attribute of the root group (the run's provenance). */
typedef struct {
  const char* name;
  int kind; /* hybridtest_hdf5_kind */
  const char* text;
  int64_t integer;
  const double* numbers;
  size_t count;
} hybridtest_hdf5_attribute;

typedef struct {
  size_t rows;
  const hybridtest_hdf5_dataset* datasets;
  size_t num_datasets;
  /* The stage record: stages_csv is NULL when the run has none. */
  const char* stages_csv;
  size_t stage_rows;
  const hybridtest_hdf5_dataset* stages;
  size_t num_stages;
  const hybridtest_hdf5_attribute* root_attributes;
  size_t num_root_attributes;
  /* /metadata's datasets config and sidecar, attributes software_version (of the exporter),
   * run_software_version and source_csv. */
  const char* config;
  const char* sidecar;
  const char* software_version;
  const char* run_software_version;
  const char* source_csv;
} hybridtest_hdf5_run;

/* Writes `run` to h5_path (created or truncated). Returns 0 on success; otherwise nonzero, with
 * what failed and HDF5's reason ("create the HDF5 file: unable to open file") in `error`,
 * NUL-terminated and cut to error_size bytes. */
typedef int (*hybridtest_hdf5_write_fn)(const hybridtest_hdf5_run* run, const char* h5_path,
                                        char* error, size_t error_size);

#ifdef __cplusplus
}
#endif
