// The FMI 3.0 co-simulation functions of an FMU written by `hybridtest export-fmu --fmi-version
// 3`: the same ExportedModel as fmi2_functions.cc behind FMI 3's names, declared by
// fmi/fmi3_api.h (from the standard's text) or, for the few the importer does not call, here
// from section 2.2 of the standard. No event mode, no early return, no intermediate update.
#include <cstring>
#include <memory>
#include <string>

#include "exported_model.h"
#include "fmu_resources.h"
#include "hybridtest/fmi/fmi3_api.h"

#define FMU_EXPORT extern "C" __attribute__((visibility("default")))

namespace {

using hybridtest::fmu_export::ExportedModel;

struct Instance3 {
  std::unique_ptr<ExportedModel> model;
  fmi3LogMessageCallback log = nullptr;
  fmi3InstanceEnvironment environment = nullptr;
};

template <typename F>
fmi3Status Guard(fmi3Instance c, const char* call, F&& f) {
  auto* in = static_cast<Instance3*>(c);
  if (in == nullptr) return fmi3Error;
  try {
    f(*in);
    return fmi3OK;
  } catch (const std::exception& e) {
    if (in->log != nullptr) {
      in->log(in->environment, fmi3Error, "logStatusError", (std::string(call) + ": " + e.what()).c_str());
    }
    return fmi3Error;
  }
}

}  // namespace

FMU_EXPORT const char* fmi3GetVersion(void) { return "3.0"; }
FMU_EXPORT fmi3Status fmi3SetDebugLogging(fmi3Instance, fmi3Boolean, size_t, const fmi3String[]) {
  return fmi3OK;
}

FMU_EXPORT fmi3Instance fmi3InstantiateCoSimulation(
    fmi3String name, fmi3String token, fmi3String resources, fmi3Boolean, fmi3Boolean,
    fmi3Boolean event_mode, fmi3Boolean early_return, const fmi3ValueReference[], size_t,
    fmi3InstanceEnvironment environment, fmi3LogMessageCallback log,
    fmi3IntermediateUpdateCallback) {
  (void)name;
  auto in = std::make_unique<Instance3>();
  in->log = log;
  in->environment = environment;
  try {
    if (event_mode || early_return) {
      throw hybridtest::Error("event mode and early return are not supported");
    }
    const std::string folder = hybridtest::fmu_export::ResourceFolder(resources != nullptr ? resources : "");
    hybridtest::fmu_export::CheckToken(folder, token != nullptr ? token : "");
    in->model = std::make_unique<ExportedModel>(folder);
  } catch (const std::exception& e) {
    if (log != nullptr) {
      log(environment, fmi3Error, "logStatusError",
          (std::string("fmi3InstantiateCoSimulation: ") + e.what()).c_str());
    }
    return nullptr;
  }
  return in.release();
}

FMU_EXPORT void fmi3FreeInstance(fmi3Instance c) { delete static_cast<Instance3*>(c); }

FMU_EXPORT fmi3Status fmi3EnterInitializationMode(fmi3Instance c, fmi3Boolean, fmi3Float64,
                                                  fmi3Float64 start, fmi3Boolean stop_defined,
                                                  fmi3Float64 stop) {
  return Guard(c, "fmi3EnterInitializationMode", [&](Instance3& in) {
    in.model->SetupExperiment(start, stop_defined ? std::optional<double>(stop) : std::nullopt);
  });
}
FMU_EXPORT fmi3Status fmi3ExitInitializationMode(fmi3Instance c) {
  return Guard(c, "fmi3ExitInitializationMode", [](Instance3& in) { in.model->Initialize(); });
}
FMU_EXPORT fmi3Status fmi3EnterStepMode(fmi3Instance c) { return c != nullptr ? fmi3OK : fmi3Error; }
FMU_EXPORT fmi3Status fmi3Terminate(fmi3Instance c) { return c != nullptr ? fmi3OK : fmi3Error; }
FMU_EXPORT fmi3Status fmi3Reset(fmi3Instance c) {
  return Guard(c, "fmi3Reset", [](Instance3&) {
    throw hybridtest::Error("not supported: free the instance and instantiate it again");
  });
}

FMU_EXPORT fmi3Status fmi3GetFloat64(fmi3Instance c, const fmi3ValueReference vr[], size_t n,
                                     fmi3Float64 values[], size_t n_values) {
  return Guard(c, "fmi3GetFloat64", [&](Instance3& in) {
    if (n != n_values) throw hybridtest::Error("every variable is a scalar: nValues = nValueReferences");
    for (size_t i = 0; i < n; ++i) values[i] = in.model->Get(vr[i]);
  });
}
FMU_EXPORT fmi3Status fmi3SetFloat64(fmi3Instance c, const fmi3ValueReference vr[], size_t n,
                                     const fmi3Float64 values[], size_t n_values) {
  return Guard(c, "fmi3SetFloat64", [&](Instance3& in) {
    if (n != n_values) throw hybridtest::Error("every variable is a scalar: nValues = nValueReferences");
    for (size_t i = 0; i < n; ++i) in.model->Set(vr[i], values[i]);
  });
}
FMU_EXPORT fmi3Status fmi3SetInt32(fmi3Instance, const fmi3ValueReference[], size_t n, const fmi3Int32[], size_t) {
  return n == 0 ? fmi3OK : fmi3Error;
}
FMU_EXPORT fmi3Status fmi3SetBoolean(fmi3Instance, const fmi3ValueReference[], size_t n, const fmi3Boolean[], size_t) {
  return n == 0 ? fmi3OK : fmi3Error;
}

FMU_EXPORT fmi3Status fmi3DoStep(fmi3Instance c, fmi3Float64 t, fmi3Float64 h, fmi3Boolean,
                                 fmi3Boolean* event, fmi3Boolean* terminate, fmi3Boolean* early,
                                 fmi3Float64* last) {
  const fmi3Status s = Guard(c, "fmi3DoStep", [&](Instance3& in) { in.model->DoStep(t, h); });
  *event = false;
  *terminate = false;
  *early = false;
  if (c != nullptr) *last = static_cast<Instance3*>(c)->model->time();
  return s;
}

// The FMU state: a heap string holding ExportedModel::SaveState()'s bytes.
FMU_EXPORT fmi3Status fmi3GetFMUState(fmi3Instance c, fmi3FMUState* state) {
  return Guard(c, "fmi3GetFMUState", [&](Instance3& in) {
    std::string bytes = in.model->SaveState();
    if (*state == nullptr) {
      *state = new std::string(std::move(bytes));
    } else {
      *static_cast<std::string*>(*state) = std::move(bytes);
    }
  });
}
FMU_EXPORT fmi3Status fmi3SetFMUState(fmi3Instance c, fmi3FMUState state) {
  return Guard(c, "fmi3SetFMUState", [&](Instance3& in) {
    if (state == nullptr) throw hybridtest::Error("no FMU state given");
    in.model->RestoreState(*static_cast<const std::string*>(state));
  });
}
FMU_EXPORT fmi3Status fmi3FreeFMUState(fmi3Instance, fmi3FMUState* state) {
  if (state != nullptr) {
    delete static_cast<std::string*>(*state);
    *state = nullptr;
  }
  return fmi3OK;
}
FMU_EXPORT fmi3Status fmi3SerializedFMUStateSize(fmi3Instance, fmi3FMUState state, size_t* size) {
  if (state == nullptr) return fmi3Error;
  *size = static_cast<const std::string*>(state)->size();
  return fmi3OK;
}
FMU_EXPORT fmi3Status fmi3SerializeFMUState(fmi3Instance, fmi3FMUState state, fmi3Byte bytes[],
                                            size_t size) {
  if (state == nullptr) return fmi3Error;
  const auto* s = static_cast<const std::string*>(state);
  if (size < s->size()) return fmi3Error;
  std::memcpy(bytes, s->data(), s->size());
  return fmi3OK;
}
FMU_EXPORT fmi3Status fmi3DeserializeFMUState(fmi3Instance, const fmi3Byte bytes[], size_t size,
                                              fmi3FMUState* state) {
  const std::string s(reinterpret_cast<const char*>(bytes), size);
  if (*state != nullptr) {
    *static_cast<std::string*>(*state) = s;
  } else {
    *state = new std::string(s);
  }
  return fmi3OK;
}
