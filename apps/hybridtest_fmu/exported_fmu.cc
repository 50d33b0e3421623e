// The model table (fmi/fmu_entry.h) of an FMU written by `hybridtest export-fmu`: thin C
// callbacks over ExportedModel (exported_model.h). The FMI 2.0 and 3.0 functions themselves
// are the shared src/hybridtest/fmi/fmu_entry.c, linked into hybridtest_fmu.so with this file
// and exported by name (exports.map). Every C++ exception becomes FMU_ERROR with its message
// in the importer's log; no exception leaves a callback.
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>

#include "exported_model.h"
#include "fmu_resources.h"
#include "hybridtest/fmi/fmu_entry.h"

namespace {

using hybridtest::fmu_export::ExportedModel;

struct Exported {
  std::unique_ptr<ExportedModel> model;
  const FmuHost* host = nullptr;
};

// Runs `f` on the instance; an exception becomes FMU_ERROR, logged as "<call>: <what>".
template <typename F>
int Guard(void* self, const char* call, F&& f) {
  auto* in = static_cast<Exported*>(self);
  try {
    f(*in->model);
    return FMU_OK;
  } catch (const std::exception& e) {
    fmu_log(in->host, FMU_ERROR, "%s: %s", call, e.what());
    return FMU_ERROR;
  }
}

void* Instantiate(const FmuHost* host, const char* token, const char* resources) {
  auto in = std::make_unique<Exported>();
  in->host = host;
  try {
    const std::string folder =
        hybridtest::fmu_export::ResourceFolder(resources != nullptr ? resources : "");
    hybridtest::fmu_export::CheckToken(folder, token != nullptr ? token : "");
    in->model = std::make_unique<ExportedModel>(folder);
  } catch (const std::exception& e) {
    fmu_log(host, FMU_ERROR, "instantiation: %s", e.what());
    return nullptr;
  }
  return in.release();
}

void FreeInstance(void* self) { delete static_cast<Exported*>(self); }

int Setup(void* self, double start, int stop_defined, double stop) {
  return Guard(self, "setting up the experiment", [&](ExportedModel& m) {
    m.SetupExperiment(start, stop_defined ? std::optional<double>(stop) : std::nullopt);
  });
}

int ExitInitialization(void* self) {
  return Guard(self, "ExitInitializationMode", [](ExportedModel& m) { m.Initialize(); });
}

int Get(void* self, const unsigned vr[], size_t n, double values[]) {
  return Guard(self, "get", [&](ExportedModel& m) {
    for (size_t i = 0; i < n; ++i) values[i] = m.Get(vr[i]);
  });
}

int Set(void* self, const unsigned vr[], size_t n, const double values[]) {
  return Guard(self, "set", [&](ExportedModel& m) {
    for (size_t i = 0; i < n; ++i) m.Set(vr[i], values[i]);
  });
}

int DoStep(void* self, double t, double h, double* time) {
  const int status = Guard(self, "DoStep", [&](ExportedModel& m) { m.DoStep(t, h); });
  *time = static_cast<Exported*>(self)->model->time();
  return status;
}

int SaveState(void* self, void** bytes, size_t* size) {
  return Guard(self, "GetFMUState", [&](ExportedModel& m) {
    const std::string state = m.SaveState();
    *bytes = std::malloc(state.size());
    if (*bytes == nullptr) throw hybridtest::Error("out of memory for the FMU state");
    std::memcpy(*bytes, state.data(), state.size());
    *size = state.size();
  });
}

int RestoreState(void* self, const void* bytes, size_t size) {
  return Guard(self, "SetFMUState", [&](ExportedModel& m) {
    m.RestoreState(std::string(static_cast<const char*>(bytes), size));
  });
}

}  // namespace

extern "C" const FmuModel fmu_model = {
    /*token=*/nullptr,  // checked against export.json by Instantiate
    Instantiate, FreeInstance, Setup, ExitInitialization, Get, Set, DoStep,
    /*reset=*/nullptr, SaveState, RestoreState,
};
