// The HDF5 writer module hybridtest_hdf5.so: writes a hybridtest_hdf5_run that
// report::ExportHdf5 prepared (src/hybridtest/report/hdf5_module.h) in the layout of
// report/hdf5_export.h. The only code of the project that links libhdf5. Its one exported
// symbol is the entry point; no exception leaves it.
#include <hdf5.h>

#include <algorithm>
#include <cstring>
#include <exception>
#include <string>
#include <type_traits>
#include <vector>

#include "hybridtest/report/hdf5_module.h"

namespace {

// Owns one HDF5 identifier and closes it with the matching H5?close.
class Handle {
 public:
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  hid_t get() const { return id_; }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

// Silences HDF5's own printing of its error stack for the lifetime of the object; errors are
// returned as text instead.
class QuietHdf5Errors {
 public:
  QuietHdf5Errors() {
    H5Eget_auto2(H5E_DEFAULT, &old_func_, &old_data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~QuietHdf5Errors() { H5Eset_auto2(H5E_DEFAULT, old_func_, old_data_); }
  QuietHdf5Errors(const QuietHdf5Errors&) = delete;
  QuietHdf5Errors& operator=(const QuietHdf5Errors&) = delete;

 private:
  H5E_auto2_t old_func_ = nullptr;
  void* old_data_ = nullptr;
};

// The innermost messages of HDF5's current error stack, e.g. "unable to open file".
std::string Hdf5ErrorText() {
  std::vector<std::string> messages;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_UPWARD,
      [](unsigned, const H5E_error2_t* error, void* data) -> herr_t {
        auto* list = static_cast<std::vector<std::string>*>(data);
        if (error->desc != nullptr && list->size() < 2) list->push_back(error->desc);
        return 0;
      },
      &messages);
  std::string text;
  for (const auto& message : messages) text += (text.empty() ? "" : "; ") + message;
  return text.empty() ? "unknown HDF5 error" : text;
}

// What failed, with HDF5's reason; caught at the entry point.
struct Failure {
  std::string text;
};

[[noreturn]] void Fail(const std::string& what) { throw Failure{what + ": " + Hdf5ErrorText()}; }
hid_t Check(hid_t id, const std::string& what) {
  if (id < 0) Fail(what);
  return id;
}
void Check(herr_t status, const std::string& what) {
  if (status < 0) Fail(what);
}

hid_t StringType(const std::string& name) {
  const hid_t type = Check(H5Tcopy(H5T_C_S1), "copy a string type");
  if (H5Tset_size(type, H5T_VARIABLE) < 0 || H5Tset_cset(type, H5T_CSET_UTF8) < 0) {
    H5Tclose(type);
    Fail("make the UTF-8 string type of " + name);
  }
  return type;
}

// A scalar (scalar = true) or 1-D attribute of `file_type` on `object`.
void WriteAttribute(hid_t object, const std::string& name, hid_t file_type, hid_t memory_type,
                    const void* data, hsize_t count, bool scalar) {
  const Handle space(Check(scalar ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &count, nullptr),
                           "create a dataspace"),
                     H5Sclose);
  const Handle attribute(Check(H5Acreate2(object, name.c_str(), file_type, space.get(),
                                          H5P_DEFAULT, H5P_DEFAULT),
                               "create attribute " + name),
                         H5Aclose);
  Check(H5Awrite(attribute.get(), memory_type, data), "write attribute " + name);
}

void WriteStringAttribute(hid_t object, const std::string& name, const char* value) {
  const Handle type(StringType(name), H5Tclose);
  const char* data = value != nullptr ? value : "";
  WriteAttribute(object, name, type.get(), type.get(), &data, 0, true);
}

void WriteStringDataset(hid_t group, const std::string& name, const char* value) {
  const Handle type(StringType(name), H5Tclose);
  const Handle space(Check(H5Screate(H5S_SCALAR), "create a scalar dataspace"), H5Sclose);
  const Handle dataset(Check(H5Dcreate2(group, name.c_str(), type.get(), space.get(),
                                        H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                             "create dataset " + name),
                       H5Dclose);
  const char* data = value != nullptr ? value : "";
  Check(H5Dwrite(dataset.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, &data),
        "write dataset " + name);
}

// The datasets of one table, each with its units, description and channel attributes, parent
// groups created on the way; gzip-compressed when the filter exists.
void WriteDatasets(hid_t file, const hybridtest_hdf5_dataset* datasets, size_t count,
                   size_t rows) {
  const hsize_t size = rows;
  const Handle links(Check(H5Pcreate(H5P_LINK_CREATE), "create a property list"), H5Pclose);
  Check(H5Pset_create_intermediate_group(links.get(), 1), "configure intermediate groups");
  const Handle layout(Check(H5Pcreate(H5P_DATASET_CREATE), "create a property list"), H5Pclose);
  if (size > 0 && H5Zfilter_avail(H5Z_FILTER_DEFLATE) > 0) {
    const hsize_t chunk = std::min<hsize_t>(size, 65536);
    Check(H5Pset_chunk(layout.get(), 1, &chunk), "chunk the datasets");
    Check(H5Pset_deflate(layout.get(), 4), "compress the datasets");
  }
  const Handle space(Check(H5Screate_simple(1, &size, nullptr), "create a dataspace"), H5Sclose);
  for (size_t i = 0; i < count; ++i) {
    const hybridtest_hdf5_dataset& d = datasets[i];
    const Handle dataset(Check(H5Dcreate2(file, d.path, H5T_IEEE_F64LE, space.get(), links.get(),
                                          layout.get(), H5P_DEFAULT),
                               std::string("create dataset ") + d.path),
                         H5Dclose);
    if (size > 0) {
      Check(H5Dwrite(dataset.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, d.values),
            std::string("write dataset ") + d.path);
    }
    WriteStringAttribute(dataset.get(), "units", d.units);
    WriteStringAttribute(dataset.get(), "description", d.description);
    WriteStringAttribute(dataset.get(), "channel", d.channel);
  }
}

void WriteRootAttribute(hid_t file, const hybridtest_hdf5_attribute& a) {
  switch (a.kind) {
    case HYBRIDTEST_HDF5_INT64:
      WriteAttribute(file, a.name, H5T_STD_I64LE, H5T_NATIVE_INT64, &a.integer, 0, true);
      return;
    case HYBRIDTEST_HDF5_DOUBLE:
      WriteAttribute(file, a.name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, a.numbers, 0, true);
      return;
    case HYBRIDTEST_HDF5_DOUBLES:
      WriteAttribute(file, a.name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, a.numbers, a.count, false);
      return;
    default: WriteStringAttribute(file, a.name, a.text); return;
  }
}

void Write(const hybridtest_hdf5_run& run, const char* h5_path) {
  const QuietHdf5Errors quiet;
  // Dense attribute storage on the root group, so that a provenance attribute (an input file's
  // text) may exceed the 64 KiB of an object header.
  const Handle create(Check(H5Pcreate(H5P_FILE_CREATE), "create a property list"), H5Pclose);
  Check(H5Pset_attr_phase_change(create.get(), 0, 0), "configure the attributes of /");
  const Handle access(Check(H5Pcreate(H5P_FILE_ACCESS), "create a property list"), H5Pclose);
  Check(H5Pset_libver_bounds(access.get(), H5F_LIBVER_V18, H5F_LIBVER_LATEST),
        "set the format version");
  const Handle file(
      Check(H5Fcreate(h5_path, H5F_ACC_TRUNC, create.get(), access.get()), "create the HDF5 file"),
      H5Fclose);
  WriteDatasets(file.get(), run.datasets, run.num_datasets, run.rows);
  if (run.stages_csv != nullptr) {
    WriteDatasets(file.get(), run.stages, run.num_stages, run.stage_rows);
    const Handle group(Check(H5Gopen2(file.get(), "/stages", H5P_DEFAULT), "open group /stages"),
                       H5Gclose);
    WriteStringAttribute(group.get(), "source_csv", run.stages_csv);
  }
  for (size_t i = 0; i < run.num_root_attributes; ++i) {
    WriteRootAttribute(file.get(), run.root_attributes[i]);
  }
  const Handle metadata(Check(H5Gcreate2(file.get(), "/metadata", H5P_DEFAULT, H5P_DEFAULT,
                                         H5P_DEFAULT),
                              "create group /metadata"),
                        H5Gclose);
  WriteStringDataset(metadata.get(), "config", run.config);
  WriteStringDataset(metadata.get(), "sidecar", run.sidecar);
  WriteStringAttribute(metadata.get(), "format", "hybridtest-hdf5/1");
  WriteStringAttribute(metadata.get(), "software_version", run.software_version);
  WriteStringAttribute(metadata.get(), "run_software_version", run.run_software_version);
  WriteStringAttribute(metadata.get(), "source_csv", run.source_csv);
  if (H5Fflush(file.get(), H5F_SCOPE_GLOBAL) < 0) Fail("flush the HDF5 file");
}

void CopyError(const std::string& text, char* error, size_t error_size) {
  if (error == nullptr || error_size == 0) return;
  const size_t n = std::min(text.size(), error_size - 1);
  std::memcpy(error, text.data(), n);
  error[n] = '\0';
}

}  // namespace

extern "C" __attribute__((visibility("default"))) int hybridtest_hdf5_write_v1(
    const hybridtest_hdf5_run* run, const char* h5_path, char* error, size_t error_size) {
  try {
    Write(*run, h5_path);
    return 0;
  } catch (const Failure& failure) {
    CopyError(failure.text, error, error_size);
  } catch (const std::exception& e) {
    CopyError(std::string("write the HDF5 file: ") + e.what(), error, error_size);
  } catch (...) {
    CopyError("write the HDF5 file: unknown error", error, error_size);
  }
  return 1;
}

// The entry point has the type report::ExportHdf5 calls it through.
static_assert(std::is_same_v<decltype(&hybridtest_hdf5_write_v1), hybridtest_hdf5_write_fn>);
