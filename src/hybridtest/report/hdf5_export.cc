// ExportHdf5 prepares the run here and hands it to the HDF5 writer module hybridtest_hdf5.so
// (hdf5_module.h, apps/hybridtest_hdf5/), loaded only when an export is done: nothing else of
// hybridtest links libhdf5.
#include "hybridtest/report/hdf5_export.h"

#include <dlfcn.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/common/module_path.h"
#include "hybridtest/common/version.h"
#include "hybridtest/io/journal.h"
#include "hybridtest/report/hdf5_module.h"

namespace hybridtest::report {
namespace {

std::string SafeName(const std::string& name) {
  std::string safe = name;
  std::replace(safe.begin(), safe.end(), '/', '_');
  if (safe == "." || safe == "..") safe = "_" + safe;
  return safe;
}

// One root attribute, owning what the C record points to.
struct Attribute {
  std::string name;
  int kind = HYBRIDTEST_HDF5_STRING;
  std::string text;
  std::int64_t integer = 0;
  std::vector<double> numbers;
};

// The provenance of the run as root attributes: every key of `value` (the sidecar) under its
// name, nested keys joined with '.', array elements by index (test.specimen,
// extra.inputs.0.sha256). Strings stay strings, integers become int64, other numbers double,
// an array of numbers one 1-D double attribute, booleans "true"/"false", null "null", an
// empty array or object "[]"/"{}".
void FlattenJson(const nlohmann::json& value, const std::string& name,
                 std::vector<Attribute>& out) {
  Attribute a;
  a.name = SafeName(name);
  if (value.is_object() && !value.empty()) {
    for (const auto& [child, item] : value.items()) {
      FlattenJson(item, name.empty() ? child : name + "." + child, out);
    }
    return;
  }
  if (value.is_array() && !value.empty() &&
      std::all_of(value.begin(), value.end(),
                  [](const nlohmann::json& v) { return v.is_number(); })) {
    a.kind = HYBRIDTEST_HDF5_DOUBLES;
    for (const auto& v : value) a.numbers.push_back(v.get<double>());
  } else if (value.is_array() && !value.empty()) {
    for (std::size_t i = 0; i < value.size(); ++i) {
      FlattenJson(value[i], name + "." + std::to_string(i), out);
    }
    return;
  } else if (value.is_number_integer()) {
    a.kind = HYBRIDTEST_HDF5_INT64;
    a.integer = value.get<std::int64_t>();
  } else if (value.is_number()) {
    a.kind = HYBRIDTEST_HDF5_DOUBLE;
    a.numbers = {value.get<double>()};
  } else if (value.is_string()) {
    a.text = value.get<std::string>();
  } else if (value.is_boolean()) {
    a.text = value.get<bool>() ? "true" : "false";
  } else {
    a.text = value.dump();  // null, [] or {}
  }
  out.push_back(std::move(a));
}

// The datasets of one table: `paths` receives their HDF5 paths (it must outlive the records).
std::vector<hybridtest_hdf5_dataset> Datasets(
    const io::RunData& run, const std::function<std::string(const std::string&)>& path_of,
    std::vector<std::string>& paths, const std::string& h5_path) {
  std::set<std::string> used;
  for (const io::Channel& channel : run.channels) {
    paths.push_back(path_of(channel.name));
    if (!used.insert(paths.back()).second) {
      throw IoError(fmt::format("{}: channels '{}' and an earlier one both map to {}; rename "
                                "one of them",
                                h5_path, channel.name, paths.back()));
    }
  }
  std::vector<hybridtest_hdf5_dataset> datasets;
  for (int j = 0; j < run.num_channels(); ++j) {
    const io::Channel& channel = run.channels[static_cast<std::size_t>(j)];
    // Eigen's default column-major storage keeps each column contiguous.
    datasets.push_back({paths[static_cast<std::size_t>(j)].c_str(), channel.name.c_str(),
                        channel.unit.c_str(), channel.description.c_str(),
                        run.values.col(j).data()});
  }
  return datasets;
}

// The writer module's entry point, loaded (once; dlopen counts the later calls) from where
// FindModule finds it. A missing module, or one that cannot be loaded or is of another
// interface version, is an IoError saying which file and how to get a working one.
hybridtest_hdf5_write_fn LoadWriter(const std::string& h5_path) {
  const ModuleLookup lookup = FindModule(HYBRIDTEST_HDF5_MODULE_FILE, "HYBRIDTEST_HDF5_MODULE");
  const std::string fix =
      "build it (cmake --build --preset release --target hybridtest_hdf5) or reinstall "
      "hybridtest, or name it with HYBRIDTEST_HDF5_MODULE";
  if (!lookup.found) {
    throw IoError(fmt::format("{}: cannot export to HDF5: the HDF5 writer {} is in none of {}; {}",
                              h5_path, HYBRIDTEST_HDF5_MODULE_FILE, lookup.searched, fix));
  }
  const std::string module = lookup.found->string();
  std::error_code error;
  if (!std::filesystem::is_regular_file(*lookup.found, error)) {
    // Only HYBRIDTEST_HDF5_MODULE names a file that may not be there (FindModule's other
    // candidates are files it found).
    throw IoError(fmt::format("{}: cannot export to HDF5: the HDF5 writer {} ({}) is not a file; "
                              "point HYBRIDTEST_HDF5_MODULE at {}, or unset it to use the "
                              "writer built or installed with hybridtest",
                              h5_path, module, lookup.searched, HYBRIDTEST_HDF5_MODULE_FILE));
  }
  void* handle = dlopen(module.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) {
    const char* reason = dlerror();
    throw IoError(fmt::format("{}: cannot export to HDF5: cannot load the HDF5 writer {}: {}; "
                              "{} (it needs libhdf5, Debian's libhdf5-dev)",
                              h5_path, module, reason != nullptr ? reason : "unknown error", fix));
  }
  void* entry = dlsym(handle, HYBRIDTEST_HDF5_ENTRY_POINT);
  if (entry == nullptr) {
    dlclose(handle);
    throw IoError(fmt::format("{}: cannot export to HDF5: {} has no entry point {} (a writer of "
                              "another hybridtest version); {}",
                              h5_path, module, HYBRIDTEST_HDF5_ENTRY_POINT, fix));
  }
  return reinterpret_cast<hybridtest_hdf5_write_fn>(entry);
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
  hybridtest_hdf5_run c{};
  std::vector<std::string> paths;
  const std::vector<hybridtest_hdf5_dataset> datasets = Datasets(run, Hdf5DatasetPath, paths, h5_path);
  c.rows = static_cast<std::size_t>(run.num_rows());
  c.datasets = datasets.data();
  c.num_datasets = datasets.size();

  // The stage record (<run>.stages.csv), when the run has one.
  const std::string stages_path = io::StagesPath(run.csv_path);
  std::error_code missing;
  io::RunData stages;
  std::vector<std::string> stage_paths;
  std::vector<hybridtest_hdf5_dataset> stage_datasets;
  if (std::filesystem::is_regular_file(stages_path, missing)) {
    stages = io::LoadRun(stages_path);
    stage_datasets = Datasets(
        stages, [](const std::string& name) { return "/stages/" + SafeName(name); },
        stage_paths, h5_path);
    c.stages_csv = stages_path.c_str();
    c.stage_rows = static_cast<std::size_t>(stages.num_rows());
    c.stages = stage_datasets.data();
    c.num_stages = stage_datasets.size();
  }

  // Provenance: the sidecar's keys as root attributes (its channel list is on the datasets).
  std::vector<Attribute> attributes;
  if (run.metadata.is_object()) {
    nlohmann::json provenance = run.metadata;
    provenance.erase("channels");
    FlattenJson(provenance, "", attributes);
  }
  std::vector<hybridtest_hdf5_attribute> root;
  for (const Attribute& a : attributes) {
    root.push_back({a.name.c_str(), a.kind, a.text.c_str(), a.integer, a.numbers.data(),
                    a.numbers.size()});
  }
  c.root_attributes = root.data();
  c.num_root_attributes = root.size();

  // Metadata: config text, the whole sidecar, versions.
  const bool has_sidecar = run.metadata.is_object();
  const auto text_of = [&](const char* key) {
    return has_sidecar && run.metadata.contains(key) && run.metadata[key].is_string()
               ? run.metadata[key].get<std::string>()
               : std::string();
  };
  const std::string config = text_of("config");
  const std::string sidecar = run.metadata.dump(2);
  const std::string run_version = text_of("software_version");
  c.config = config.c_str();
  c.sidecar = sidecar.c_str();
  c.software_version = kVersion;
  c.run_software_version = run_version.c_str();
  c.source_csv = run.csv_path.c_str();

  const hybridtest_hdf5_write_fn write = LoadWriter(h5_path);
  std::array<char, 1024> error{};
  if (write(&c, h5_path.c_str(), error.data(), error.size()) != 0) {
    throw IoError(fmt::format("{}: cannot {}; check that the directory exists, is writable and "
                              "has free space",
                              h5_path, error.data()));
  }
}

}  // namespace hybridtest::report
