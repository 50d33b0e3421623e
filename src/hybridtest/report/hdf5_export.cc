#include "hybridtest/report/hdf5_export.h"

#include <fmt/format.h>
#include <hdf5.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <set>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/common/version.h"
#include "hybridtest/io/journal.h"

namespace hybridtest::report {
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
// reported by IoError instead.
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

class Writer {
 public:
  explicit Writer(std::string path) : path_(std::move(path)) {}

  [[noreturn]] void Fail(const std::string& what) const {
    throw IoError(fmt::format("{}: cannot {}: {}; check that the directory exists, is writable "
                              "and has free space",
                              path_, what, Hdf5ErrorText()));
  }
  hid_t Check(hid_t id, const std::string& what) const {
    if (id < 0) Fail(what);
    return id;
  }
  void Check(herr_t status, const char* what, const std::string& name) const {
    if (status < 0) Fail(fmt::format("{} {}", what, name));
  }

  // Writes a scalar variable-length UTF-8 string attribute on `object`.
  void WriteStringAttribute(hid_t object, const std::string& name, const std::string& value) {
    const Handle type(Check(H5Tcopy(H5T_C_S1), "copy a string type"), H5Tclose);
    Check(H5Tset_size(type.get(), H5T_VARIABLE), "size a string type", name);
    Check(H5Tset_cset(type.get(), H5T_CSET_UTF8), "set UTF-8 on", name);
    const Handle space(Check(H5Screate(H5S_SCALAR), "create a scalar dataspace"), H5Sclose);
    const Handle attribute(Check(H5Acreate2(object, name.c_str(), type.get(), space.get(),
                                            H5P_DEFAULT, H5P_DEFAULT),
                                 "create attribute " + name),
                           H5Aclose);
    const char* data = value.c_str();
    Check(H5Awrite(attribute.get(), type.get(), &data), "write attribute", name);
  }

  // Writes a scalar (count 0) or 1-D (count ≥ 1) attribute of `type` on `object`.
  void WriteAttribute(hid_t object, const std::string& name, hid_t file_type, hid_t memory_type,
                      const void* data, hsize_t count, bool scalar) {
    const Handle space(Check(scalar ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &count, nullptr),
                             "create a dataspace"),
                       H5Sclose);
    const Handle attribute(Check(H5Acreate2(object, name.c_str(), file_type, space.get(),
                                            H5P_DEFAULT, H5P_DEFAULT),
                                 "create attribute " + name),
                           H5Aclose);
    Check(H5Awrite(attribute.get(), memory_type, data), "write attribute", name);
  }

  // Writes a scalar variable-length UTF-8 string dataset at `name` in `group`.
  void WriteStringDataset(hid_t group, const std::string& name, const std::string& value) {
    const Handle type(Check(H5Tcopy(H5T_C_S1), "copy a string type"), H5Tclose);
    Check(H5Tset_size(type.get(), H5T_VARIABLE), "size a string type", name);
    Check(H5Tset_cset(type.get(), H5T_CSET_UTF8), "set UTF-8 on", name);
    const Handle space(Check(H5Screate(H5S_SCALAR), "create a scalar dataspace"), H5Sclose);
    const Handle dataset(Check(H5Dcreate2(group, name.c_str(), type.get(), space.get(),
                                          H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                               "create dataset " + name),
                         H5Dclose);
    const char* data = value.c_str();
    Check(H5Dwrite(dataset.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, &data),
          "write dataset", name);
  }

  // Writes a 1-D double dataset at the absolute path `name`, creating parent groups.
  hid_t CreateDoubleDataset(hid_t file, const std::string& name, const double* data,
                            hsize_t size) {
    const Handle links(Check(H5Pcreate(H5P_LINK_CREATE), "create a property list"), H5Pclose);
    Check(H5Pset_create_intermediate_group(links.get(), 1), "configure groups for", name);
    const Handle layout(Check(H5Pcreate(H5P_DATASET_CREATE), "create a property list"),
                        H5Pclose);
    if (size > 0 && H5Zfilter_avail(H5Z_FILTER_DEFLATE) > 0) {
      const hsize_t chunk = std::min<hsize_t>(size, 65536);
      Check(H5Pset_chunk(layout.get(), 1, &chunk), "chunk", name);
      Check(H5Pset_deflate(layout.get(), 4), "compress", name);
    }
    const Handle space(Check(H5Screate_simple(1, &size, nullptr), "create a dataspace"),
                       H5Sclose);
    const hid_t dataset = Check(H5Dcreate2(file, name.c_str(), H5T_IEEE_F64LE, space.get(),
                                           links.get(), layout.get(), H5P_DEFAULT),
                                "create dataset " + name);
    if (size > 0 &&
        H5Dwrite(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0) {
      H5Dclose(dataset);
      Fail("write dataset " + name);
    }
    return dataset;
  }

 private:
  std::string path_;
};

std::string SafeName(const std::string& name) {
  std::string safe = name;
  std::replace(safe.begin(), safe.end(), '/', '_');
  if (safe == "." || safe == "..") safe = "_" + safe;
  return safe;
}

// The provenance of the run as attributes of `object`: every key of `value` (the sidecar)
// under its name, nested keys joined with '.', array elements by index (test.specimen,
// extra.inputs.0.sha256). Strings stay strings, integers become int64, other numbers double,
// an array of numbers one 1-D double attribute, booleans "true"/"false", null "null", an
// empty array or object "[]"/"{}".
void WriteJsonAttributes(Writer& writer, hid_t object, const nlohmann::json& value,
                         const std::string& name) {
  const std::string key = SafeName(name);
  if (value.is_object() && !value.empty()) {
    for (const auto& [child, item] : value.items()) {
      WriteJsonAttributes(writer, object, item, name.empty() ? child : name + "." + child);
    }
  } else if (value.is_array() && !value.empty() &&
             std::all_of(value.begin(), value.end(),
                         [](const nlohmann::json& v) { return v.is_number(); })) {
    std::vector<double> numbers;
    for (const auto& v : value) numbers.push_back(v.get<double>());
    writer.WriteAttribute(object, key, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, numbers.data(),
                          numbers.size(), false);
  } else if (value.is_array() && !value.empty()) {
    for (std::size_t i = 0; i < value.size(); ++i) {
      WriteJsonAttributes(writer, object, value[i], name + "." + std::to_string(i));
    }
  } else if (value.is_number_integer()) {
    const std::int64_t v = value.get<std::int64_t>();
    writer.WriteAttribute(object, key, H5T_STD_I64LE, H5T_NATIVE_INT64, &v, 0, true);
  } else if (value.is_number()) {
    const double v = value.get<double>();
    writer.WriteAttribute(object, key, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &v, 0, true);
  } else if (value.is_string()) {
    writer.WriteStringAttribute(object, key, value.get<std::string>());
  } else if (value.is_boolean()) {
    writer.WriteStringAttribute(object, key, value.get<bool>() ? "true" : "false");
  } else {
    writer.WriteStringAttribute(object, key, value.dump());  // null, [] or {}
  }
}

// One 1-D dataset per channel under `prefix`, with the units, description and channel
// attributes.
void WriteChannels(Writer& writer, hid_t file, const io::RunData& run,
                   const std::function<std::string(const std::string&)>& path_of,
                   const std::string& h5_path) {
  const auto rows = static_cast<hsize_t>(run.values.rows());
  std::set<std::string> used;
  for (int j = 0; j < run.num_channels(); ++j) {
    const io::Channel& channel = run.channels[static_cast<std::size_t>(j)];
    const std::string path = path_of(channel.name);
    if (!used.insert(path).second) {
      throw IoError(fmt::format("{}: channels '{}' and an earlier one both map to {}; rename "
                                "one of them",
                                h5_path, channel.name, path));
    }
    // Eigen's default column-major storage keeps each column contiguous.
    const Handle dataset(
        writer.CreateDoubleDataset(file, path, run.values.col(j).data(), rows), H5Dclose);
    writer.WriteStringAttribute(dataset.get(), "units", channel.unit);
    writer.WriteStringAttribute(dataset.get(), "description", channel.description);
    writer.WriteStringAttribute(dataset.get(), "channel", channel.name);
  }
}

}  // namespace

std::string Hdf5DatasetPath(const std::string& channel_name) {
  const io::ChannelClass c = io::ClassifyChannel(channel_name);
  switch (c.kind) {
    case io::ChannelKind::kTime: return "/time/" + SafeName(channel_name);
    case io::ChannelKind::kCoordinate: return "/coordinates/" + SafeName(channel_name);
    case io::ChannelKind::kSpeed: return "/speeds/" + SafeName(channel_name);
    case io::ChannelKind::kRestoringForce: return "/restoring_forces/" + SafeName(channel_name);
    case io::ChannelKind::kPhysical: return "/physical/" + SafeName(c.slot) + "/" + c.field;
    case io::ChannelKind::kOther: break;
  }
  return "/other/" + SafeName(channel_name);
}

void ExportHdf5(const io::RunData& run, const std::string& h5_path) {
  const QuietHdf5Errors quiet;
  Writer writer(h5_path);
  // Dense attribute storage on the root group, so that a provenance attribute (an input file's
  // text) may exceed the 64 KiB of an object header.
  const Handle create(writer.Check(H5Pcreate(H5P_FILE_CREATE), "create a property list"),
                      H5Pclose);
  writer.Check(H5Pset_attr_phase_change(create.get(), 0, 0), "configure attributes of", "/");
  const Handle access(writer.Check(H5Pcreate(H5P_FILE_ACCESS), "create a property list"),
                      H5Pclose);
  writer.Check(H5Pset_libver_bounds(access.get(), H5F_LIBVER_V18, H5F_LIBVER_LATEST),
               "set the format version of", h5_path);
  const Handle file(
      writer.Check(H5Fcreate(h5_path.c_str(), H5F_ACC_TRUNC, create.get(), access.get()),
                   "create the HDF5 file"),
      H5Fclose);

  WriteChannels(writer, file.get(), run, Hdf5DatasetPath, h5_path);

  // The stage record (<run>.stages.csv), when the run has one.
  const std::string stages_path = io::StagesPath(run.csv_path);
  std::error_code missing;
  if (std::filesystem::is_regular_file(stages_path, missing)) {
    const io::RunData stages = io::LoadRun(stages_path);
    WriteChannels(
        writer, file.get(), stages,
        [](const std::string& name) { return "/stages/" + SafeName(name); }, h5_path);
    const Handle group(writer.Check(H5Gopen2(file.get(), "/stages", H5P_DEFAULT),
                                    "open group /stages"),
                       H5Gclose);
    writer.WriteStringAttribute(group.get(), "source_csv", stages_path);
  }

  // Provenance: the sidecar's keys as root attributes (its channel list is on the datasets).
  if (run.metadata.is_object()) {
    nlohmann::json provenance = run.metadata;
    provenance.erase("channels");
    WriteJsonAttributes(writer, file.get(), provenance, "");
  }

  // Metadata: config text, the whole sidecar, versions.
  const Handle metadata(writer.Check(H5Gcreate2(file.get(), "/metadata", H5P_DEFAULT,
                                                H5P_DEFAULT, H5P_DEFAULT),
                                     "create group /metadata"),
                        H5Gclose);
  const bool has_sidecar = run.metadata.is_object();
  const auto text_of = [&](const char* key) {
    return has_sidecar && run.metadata.contains(key) && run.metadata[key].is_string()
               ? run.metadata[key].get<std::string>()
               : std::string();
  };
  writer.WriteStringDataset(metadata.get(), "config", text_of("config"));
  writer.WriteStringDataset(metadata.get(), "sidecar", run.metadata.dump(2));
  writer.WriteStringAttribute(metadata.get(), "format", "hybridtest-hdf5/1");
  writer.WriteStringAttribute(metadata.get(), "software_version", kVersion);
  writer.WriteStringAttribute(metadata.get(), "run_software_version", text_of("software_version"));
  writer.WriteStringAttribute(metadata.get(), "source_csv", run.csv_path);

  if (H5Fflush(file.get(), H5F_SCOPE_GLOBAL) < 0) writer.Fail("flush the HDF5 file");
}

}  // namespace hybridtest::report
