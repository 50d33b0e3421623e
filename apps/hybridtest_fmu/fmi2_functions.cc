// The FMI 2.0 co-simulation functions of an FMU written by `hybridtest export-fmu`: thin C
// wrappers of ExportedModel (exported_model.h), declared by fmi/fmi2_api.h (from the
// standard's text). Every C++ exception becomes fmi2Error with its message in the log; no
// exception leaves a function. Exported by name from hybridtest_fmu.so (exports.map).
#include <cstring>
#include <memory>
#include <string>

#include "exported_model.h"
#include "fmu_resources.h"
#include "hybridtest/fmi/fmi2_api.h"

#define FMU_EXPORT extern "C" __attribute__((visibility("default")))

namespace {

using hybridtest::fmu_export::ExportedModel;

struct Instance {
  std::unique_ptr<ExportedModel> model;
  fmi2CallbackLogger logger = nullptr;
  fmi2ComponentEnvironment environment = nullptr;
  std::string name;
  bool stop_defined = false;
  double stop = 0.0;
};

void Log(const Instance* in, fmi2Status status, const std::string& message) {
  if (in->logger != nullptr) {
    in->logger(in->environment, in->name.c_str(), status,
               status == fmi2OK ? "logEvents" : "logStatusError", "%s", message.c_str());
  }
}

// Runs `f` on the instance; an exception becomes fmi2Error, logged.
template <typename F>
fmi2Status Guard(fmi2Component c, const char* call, F&& f) {
  auto* in = static_cast<Instance*>(c);
  if (in == nullptr) return fmi2Error;
  try {
    f(*in);
    return fmi2OK;
  } catch (const std::exception& e) {
    Log(in, fmi2Error, std::string(call) + ": " + e.what());
    return fmi2Error;
  }
}

fmi2Status NoValues(size_t n) { return n == 0 ? fmi2OK : fmi2Error; }

}  // namespace

FMU_EXPORT const char* fmi2GetTypesPlatform(void) { return "default"; }
FMU_EXPORT const char* fmi2GetVersion(void) { return "2.0"; }

FMU_EXPORT fmi2Status fmi2SetDebugLogging(fmi2Component, fmi2Boolean, size_t, const fmi2String[]) {
  return fmi2OK;
}

FMU_EXPORT fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid,
                                         fmi2String resources,
                                         const fmi2CallbackFunctions* functions, fmi2Boolean,
                                         fmi2Boolean) {
  auto in = std::make_unique<Instance>();
  in->name = name != nullptr ? name : "";
  if (functions != nullptr) {
    in->logger = functions->logger;
    in->environment = functions->componentEnvironment;
  }
  try {
    if (type != fmi2CoSimulation) {
      throw hybridtest::Error("this FMU is for co-simulation only (fmi2CoSimulation)");
    }
    const std::string folder = hybridtest::fmu_export::ResourceFolder(resources != nullptr ? resources : "");
    hybridtest::fmu_export::CheckToken(folder, guid != nullptr ? guid : "");
    in->model = std::make_unique<ExportedModel>(folder);
  } catch (const std::exception& e) {
    Log(in.get(), fmi2Error, std::string("fmi2Instantiate: ") + e.what());
    return nullptr;
  }
  return in.release();
}

FMU_EXPORT void fmi2FreeInstance(fmi2Component c) { delete static_cast<Instance*>(c); }

FMU_EXPORT fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean, fmi2Real, fmi2Real start,
                                          fmi2Boolean stop_defined, fmi2Real stop) {
  return Guard(c, "fmi2SetupExperiment", [&](Instance& in) {
    in.model->SetupExperiment(start, stop_defined ? std::optional<double>(stop) : std::nullopt);
  });
}

FMU_EXPORT fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
  return c != nullptr ? fmi2OK : fmi2Error;
}

FMU_EXPORT fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
  return Guard(c, "fmi2ExitInitializationMode", [](Instance& in) { in.model->Initialize(); });
}

FMU_EXPORT fmi2Status fmi2Terminate(fmi2Component c) { return c != nullptr ? fmi2OK : fmi2Error; }

FMU_EXPORT fmi2Status fmi2Reset(fmi2Component c) {
  return Guard(c, "fmi2Reset", [](Instance&) {
    throw hybridtest::Error("not supported: free the instance and instantiate it again");
  });
}

FMU_EXPORT fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                  fmi2Real value[]) {
  return Guard(c, "fmi2GetReal", [&](Instance& in) {
    for (size_t i = 0; i < n; ++i) value[i] = in.model->Get(vr[i]);
  });
}

FMU_EXPORT fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                  const fmi2Real value[]) {
  return Guard(c, "fmi2SetReal", [&](Instance& in) {
    for (size_t i = 0; i < n; ++i) in.model->Set(vr[i], value[i]);
  });
}

FMU_EXPORT fmi2Status fmi2GetInteger(fmi2Component, const fmi2ValueReference[], size_t n, fmi2Integer[]) { return NoValues(n); }
FMU_EXPORT fmi2Status fmi2SetInteger(fmi2Component, const fmi2ValueReference[], size_t n, const fmi2Integer[]) { return NoValues(n); }
FMU_EXPORT fmi2Status fmi2GetBoolean(fmi2Component, const fmi2ValueReference[], size_t n, fmi2Boolean[]) { return NoValues(n); }
FMU_EXPORT fmi2Status fmi2SetBoolean(fmi2Component, const fmi2ValueReference[], size_t n, const fmi2Boolean[]) { return NoValues(n); }
FMU_EXPORT fmi2Status fmi2GetString(fmi2Component, const fmi2ValueReference[], size_t n, fmi2String[]) { return NoValues(n); }
FMU_EXPORT fmi2Status fmi2SetString(fmi2Component, const fmi2ValueReference[], size_t n, const fmi2String[]) { return NoValues(n); }

// The FMU state: a heap string holding ExportedModel::SaveState()'s bytes.
FMU_EXPORT fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate* state) {
  return Guard(c, "fmi2GetFMUstate", [&](Instance& in) {
    std::string bytes = in.model->SaveState();
    if (*state == nullptr) {
      *state = new std::string(std::move(bytes));
    } else {
      *static_cast<std::string*>(*state) = std::move(bytes);
    }
  });
}

FMU_EXPORT fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate state) {
  return Guard(c, "fmi2SetFMUstate", [&](Instance& in) {
    if (state == nullptr) throw hybridtest::Error("no FMU state given");
    in.model->RestoreState(*static_cast<const std::string*>(state));
  });
}

FMU_EXPORT fmi2Status fmi2FreeFMUstate(fmi2Component, fmi2FMUstate* state) {
  if (state != nullptr) {
    delete static_cast<std::string*>(*state);
    *state = nullptr;
  }
  return fmi2OK;
}

FMU_EXPORT fmi2Status fmi2SerializedFMUstateSize(fmi2Component, fmi2FMUstate state, size_t* size) {
  if (state == nullptr) return fmi2Error;
  *size = static_cast<const std::string*>(state)->size();
  return fmi2OK;
}

FMU_EXPORT fmi2Status fmi2SerializeFMUstate(fmi2Component, fmi2FMUstate state, fmi2Byte bytes[],
                                            size_t size) {
  if (state == nullptr) return fmi2Error;
  const auto* s = static_cast<const std::string*>(state);
  if (size < s->size()) return fmi2Error;
  std::memcpy(bytes, s->data(), s->size());
  return fmi2OK;
}

FMU_EXPORT fmi2Status fmi2DeSerializeFMUstate(fmi2Component, const fmi2Byte bytes[], size_t size,
                                              fmi2FMUstate* state) {
  if (*state != nullptr) {
    static_cast<std::string*>(*state)->assign(bytes, size);
  } else {
    *state = new std::string(bytes, size);
  }
  return fmi2OK;
}

FMU_EXPORT fmi2Status fmi2GetDirectionalDerivative(fmi2Component, const fmi2ValueReference[], size_t,
                                                   const fmi2ValueReference[], size_t,
                                                   const fmi2Real[], fmi2Real[]) {
  return fmi2Error;  // not declared (providesDirectionalDerivative is false)
}
FMU_EXPORT fmi2Status fmi2SetRealInputDerivatives(fmi2Component, const fmi2ValueReference[], size_t,
                                                  const fmi2Integer[], const fmi2Real[]) {
  return fmi2Error;  // canInterpolateInputs is false
}
FMU_EXPORT fmi2Status fmi2GetRealOutputDerivatives(fmi2Component, const fmi2ValueReference[], size_t,
                                                   const fmi2Integer[], fmi2Real[]) {
  return fmi2Error;  // maxOutputDerivativeOrder is 0
}

FMU_EXPORT fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean) {
  return Guard(c, "fmi2DoStep", [&](Instance& in) { in.model->DoStep(t, h); });
}

FMU_EXPORT fmi2Status fmi2CancelStep(fmi2Component) { return fmi2Error; }  // DoStep is synchronous

FMU_EXPORT fmi2Status fmi2GetStatus(fmi2Component, const fmi2StatusKind, fmi2Status*) { return fmi2Discard; }
FMU_EXPORT fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind kind, fmi2Real* value) {
  if (c == nullptr || kind != fmi2LastSuccessfulTime) return fmi2Discard;
  *value = static_cast<Instance*>(c)->model->time();
  return fmi2OK;
}
FMU_EXPORT fmi2Status fmi2GetIntegerStatus(fmi2Component, const fmi2StatusKind, fmi2Integer*) { return fmi2Discard; }
FMU_EXPORT fmi2Status fmi2GetBooleanStatus(fmi2Component, const fmi2StatusKind, fmi2Boolean*) { return fmi2Discard; }
FMU_EXPORT fmi2Status fmi2GetStringStatus(fmi2Component, const fmi2StatusKind, fmi2String*) { return fmi2Discard; }
