/* The entry points of a co-simulation FMU, written once for every FMU hybridtest builds (the
 * export-fmu binary, the example FMUs of examples/fmi/ and the test FMUs of tests/fmi/fmus/).
 *
 * fmu_entry.c defines every function the FMI 2.0 header fmi2Functions.h and the FMI 3.0 header
 * fmi3Functions.h declare (both sets in one binary; a strict importer looks up all of them for
 * the interfaces the description declares, and refuses the FMU if one is missing). They call
 * the model through the table below, which each FMU defines once as `fmu_model`. What the
 * table leaves NULL, and what this kind of FMU cannot do at all (model exchange, scheduled
 * execution, event mode, clocks, directional derivatives, values of types other than Float64 /
 * Real), returns Error (FMI 2: fmi2Error, FMI 3: fmi3Error) and logs why through the importer's
 * logger, as the standard allows for optional capabilities the description does not declare.
 *
 * Every variable is a scalar Float64 (FMI 2: Real). The FMU state of get/set/serialize is the
 * byte string the model's save_state writes; fmu_entry.c keeps it, copies it out
 * (serialize) and hands it back to restore_state (set). Status values are the FMI ones
 * (FMU_OK = fmi2OK = fmi3OK, ...). Plain C: an FMU written by hand needs this header,
 * fmu_entry.c and its own model file (docs/fmi.md, "Writing an FMU").
 */
#ifndef HYBRIDTEST_FMI_FMU_ENTRY_H_
#define HYBRIDTEST_FMI_FMU_ENTRY_H_

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

enum { FMU_OK = 0, FMU_WARNING = 1, FMU_DISCARD = 2, FMU_ERROR = 3, FMU_FATAL = 4 };

/* What the importer gave an instance: its name, FMI version and logger. */
typedef struct FmuHost FmuHost;

/* Logs through the importer's logger (category "logStatusError" for FMU_ERROR and worse,
 * "logEvents" otherwise); `format` is printf-like. Does nothing without a logger. */
void fmu_log(const FmuHost* host, int status, const char* format, ...)
    __attribute__((format(printf, 3, 4)));
/* 2 or 3: the interface the importer instantiated. */
int fmu_host_version(const FmuHost* host);

typedef struct FmuModel {
  /* The guid (FMI 2) / instantiationToken (FMI 3) the importer must pass; NULL: the model's
   * instantiate checks it. */
  const char* token;
  /* A new instance (NULL after logging why). `resources` as the importer passed it: a file
   * URI (FMI 2) or a folder path (FMI 3), possibly NULL. `host` lives as long as the
   * instance. */
  void* (*instantiate)(const FmuHost* host, const char* token, const char* resources);
  void (*free_instance)(void* self);
  /* Enter initialization mode: the start time and, if stop_defined, the stop time [s]. */
  int (*setup)(void* self, double start, int stop_defined, double stop);
  int (*exit_initialization)(void* self); /* NULL: nothing to do */
  int (*get)(void* self, const unsigned vr[], size_t n, double values[]);
  int (*set)(void* self, const unsigned vr[], size_t n, const double values[]);
  /* One communication step from t of h [s]; *time: the FMU's time after it. */
  int (*do_step)(void* self, double t, double h, double* time);
  int (*reset)(void* self); /* NULL: not supported */
  /* The FMU state (NULL: canGetAndSetFMUState is false): save_state returns a malloc'ed
   * byte string in *bytes, *size; restore_state sets the instance to such a string. */
  int (*save_state)(void* self, void** bytes, size_t* size);
  int (*restore_state)(void* self, const void* bytes, size_t size);
} FmuModel;

/* For a model whose state is one fixed-size record: save_state's copy of it (malloc'ed), and
 * restore_state's check of the size (logged) and copy back. */
int fmu_save_record(const void* record, size_t size, void** bytes, size_t* out_size);
int fmu_restore_record(const FmuHost* host, void* record, size_t size, const void* bytes,
                       size_t in_size);

/* Defined by each FMU (its model file). */
extern const FmuModel fmu_model __attribute__((visibility("hidden")));

#ifdef __cplusplus
}
#endif

#endif /* HYBRIDTEST_FMI_FMU_ENTRY_H_ */
