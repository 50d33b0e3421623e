// See fmu2_instance.h.
#include "hybridtest/fmi/fmu2_instance.h"

#include <dlfcn.h>
#include <fmt/core.h>

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "hybridtest/common/error.h"

namespace hybridtest::fmi {
namespace {

const char* StatusName(fmi2Status s) {
  switch (s) {
    case fmi2OK: return "OK";
    case fmi2Warning: return "Warning";
    case fmi2Discard: return "Discard";
    case fmi2Error: return "Error";
    case fmi2Fatal: return "Fatal";
    case fmi2Pending: return "Pending";
  }
  return "?";
}

void* Allocate(size_t n, size_t size) { return std::calloc(n, size); }
void Free(void* p) { std::free(p); }

}  // namespace

LogSink StderrLog() {
  return [](const std::string& line) { std::cerr << line << '\n'; };
}

struct Fmu2Instance::Functions {
  fmi2InstantiateTYPE* instantiate = nullptr;
  fmi2FreeInstanceTYPE* free_instance = nullptr;
  fmi2SetupExperimentTYPE* setup_experiment = nullptr;
  fmi2EnterInitializationModeTYPE* enter_initialization = nullptr;
  fmi2ExitInitializationModeTYPE* exit_initialization = nullptr;
  fmi2TerminateTYPE* terminate = nullptr;
  fmi2GetRealTYPE* get_real = nullptr;
  fmi2SetRealTYPE* set_real = nullptr;
  fmi2SetIntegerTYPE* set_integer = nullptr;
  fmi2SetBooleanTYPE* set_boolean = nullptr;
  fmi2DoStepTYPE* do_step = nullptr;
  fmi2GetFMUstateTYPE* get_state = nullptr;
  fmi2SetFMUstateTYPE* set_state = nullptr;
  fmi2FreeFMUstateTYPE* free_state = nullptr;
  fmi2SerializedFMUstateSizeTYPE* serialized_size = nullptr;
  fmi2SerializeFMUstateTYPE* serialize = nullptr;
  fmi2DeSerializeFMUstateTYPE* deserialize = nullptr;
};

template <typename F>
F* Fmu2Instance::Symbol(const char* name, bool required) {
  void* p = dlsym(library_, name);
  if (p == nullptr && required) {
    throw ConfigError(fmt::format("{}: its binary exports no {} (an FMI 2.0 co-simulation FMU "
                                  "must export it); re-export the FMU with its binary",
                                  fmu_, name));
  }
  return reinterpret_cast<F*>(p);
}

Fmu2Instance::Fmu2Instance(const std::string& dir, const ModelDescription& md, std::string fmu,
                           std::string instance_name, LogSink log)
    : fmu_(std::move(fmu)), instance_name_(std::move(instance_name)), log_(std::move(log)),
      f_(std::make_unique<Functions>()) {
  namespace fs = std::filesystem;
  const fs::path so =
      fs::path(dir) / "binaries" / kFmi2Platform / (md.model_identifier + ".so");
  if (!fs::exists(so)) {
    throw ConfigError(fmt::format("{}: no binary for this platform: binaries/{}/{}.so is "
                                  "missing; export the FMU for Linux x86-64 (a binary FMU, "
                                  "platform {})", fmu_, kFmi2Platform, md.model_identifier,
                                  kFmi2Platform));
  }
  library_ = dlopen(so.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (library_ == nullptr) {
    throw ConfigError(fmt::format("{}: cannot load binaries/{}/{}.so: {}", fmu_, kFmi2Platform,
                                  md.model_identifier, dlerror()));
  }
  try {
    LoadAndInstantiate(dir, md);
  } catch (...) {
    dlclose(library_);  // the destructor does not run for a constructor that throws
    throw;
  }
}

void Fmu2Instance::LoadAndInstantiate(const std::string& dir, const ModelDescription& md) {
  namespace fs = std::filesystem;
  f_->instantiate = Symbol<fmi2InstantiateTYPE>("fmi2Instantiate", true);
  f_->free_instance = Symbol<fmi2FreeInstanceTYPE>("fmi2FreeInstance", true);
  f_->setup_experiment = Symbol<fmi2SetupExperimentTYPE>("fmi2SetupExperiment", true);
  f_->enter_initialization =
      Symbol<fmi2EnterInitializationModeTYPE>("fmi2EnterInitializationMode", true);
  f_->exit_initialization =
      Symbol<fmi2ExitInitializationModeTYPE>("fmi2ExitInitializationMode", true);
  f_->terminate = Symbol<fmi2TerminateTYPE>("fmi2Terminate", true);
  f_->get_real = Symbol<fmi2GetRealTYPE>("fmi2GetReal", true);
  f_->set_real = Symbol<fmi2SetRealTYPE>("fmi2SetReal", true);
  f_->set_integer = Symbol<fmi2SetIntegerTYPE>("fmi2SetInteger", true);
  f_->set_boolean = Symbol<fmi2SetBooleanTYPE>("fmi2SetBoolean", true);
  f_->do_step = Symbol<fmi2DoStepTYPE>("fmi2DoStep", true);
  const bool state = md.can_get_and_set_state;
  f_->get_state = Symbol<fmi2GetFMUstateTYPE>("fmi2GetFMUstate", state);
  f_->set_state = Symbol<fmi2SetFMUstateTYPE>("fmi2SetFMUstate", state);
  f_->free_state = Symbol<fmi2FreeFMUstateTYPE>("fmi2FreeFMUstate", state);
  const bool serial = md.can_serialize_state;
  f_->serialized_size =
      Symbol<fmi2SerializedFMUstateSizeTYPE>("fmi2SerializedFMUstateSize", serial);
  f_->serialize = Symbol<fmi2SerializeFMUstateTYPE>("fmi2SerializeFMUstate", serial);
  f_->deserialize = Symbol<fmi2DeSerializeFMUstateTYPE>("fmi2DeSerializeFMUstate", serial);

  callbacks_.reset(new fmi2CallbackFunctions{&Logger, &Allocate, &Free, nullptr, this});
  const std::string resources =
      "file://" + (fs::absolute(fs::path(dir)) / "resources").lexically_normal().string();
  component_ = f_->instantiate(instance_name_.c_str(), fmi2CoSimulation, md.guid.c_str(),
                               resources.c_str(), callbacks_.get(), fmi2False, fmi2False);
  if (component_ == nullptr) {
    std::string lines;
    for (const auto& line : recent_) lines += "\n  " + line;
    throw TransferError(fmt::format("{}: fmi2Instantiate failed (guid {}){}", fmu_, md.guid,
                                    lines.empty() ? " and the FMU logged nothing" : lines));
  }
}

Fmu2Instance::~Fmu2Instance() {
  if (component_ != nullptr && !fatal_) {
    if (snapshot_ != nullptr && !failed_) f_->free_state(component_, &snapshot_);
    if (initialized_ && !failed_) f_->terminate(component_);
    f_->free_instance(component_);
  }
  if (library_ != nullptr) dlclose(library_);
}

void Fmu2Instance::Logger(fmi2ComponentEnvironment env, fmi2String instance, fmi2Status status,
                          fmi2String category, fmi2String message, ...) {
  auto* self = static_cast<Fmu2Instance*>(env);
  char text[1024];
  va_list args;
  va_start(args, message);
  std::vsnprintf(text, sizeof text, message != nullptr ? message : "", args);
  va_end(args);
  const std::string line = fmt::format("fmu {}: {} [{}] {}", instance != nullptr ? instance : "?",
                                       StatusName(status), category != nullptr ? category : "",
                                       text);
  if (self == nullptr) return;
  self->recent_.push_back(line);
  if (self->recent_.size() > 8) self->recent_.pop_front();
  if (self->log_) self->log_(line);
}

void Fmu2Instance::Check(fmi2Status status, const std::string& call) {
  if (status == fmi2OK || status == fmi2Warning) return;
  if (status == fmi2Fatal) fatal_ = true;
  if (status == fmi2Error || status == fmi2Discard || status == fmi2Pending) failed_ = true;
  std::string log;
  for (const auto& line : recent_) log += "\n  " + line;
  throw TransferError(fmt::format("{}: {} returned fmi2{}{}", fmu_, call, StatusName(status),
                                  log.empty() ? " (the FMU logged nothing)"
                                              : "; the FMU's last messages:" + log));
}

void Fmu2Instance::Initialize(double start_time, const std::vector<Value>& parameters) {
  Check(f_->setup_experiment(component_, fmi2False, 0.0, start_time, fmi2False, 0.0),
        "fmi2SetupExperiment");
  for (const Value& p : parameters) {
    const fmi2ValueReference vr = p.variable->value_reference;
    const std::string call = "setting parameter " + p.variable->name;
    if (p.variable->type == "Real") {
      Check(f_->set_real(component_, &vr, 1, &p.value), call);
    } else if (p.variable->type == "Boolean") {
      const fmi2Boolean b = p.value != 0.0 ? fmi2True : fmi2False;
      Check(f_->set_boolean(component_, &vr, 1, &b), call);
    } else {
      const auto i = static_cast<fmi2Integer>(std::lround(p.value));
      Check(f_->set_integer(component_, &vr, 1, &i), call);
    }
  }
  Check(f_->enter_initialization(component_), "fmi2EnterInitializationMode");
  Check(f_->exit_initialization(component_), "fmi2ExitInitializationMode");
  initialized_ = true;
}

void Fmu2Instance::SetReal(const std::vector<fmi2ValueReference>& vr,
                           const std::vector<double>& values) {
  Check(f_->set_real(component_, vr.data(), vr.size(), values.data()), "fmi2SetReal");
}

void Fmu2Instance::GetReal(const std::vector<fmi2ValueReference>& vr, std::vector<double>& values) {
  values.resize(vr.size());
  Check(f_->get_real(component_, vr.data(), vr.size(), values.data()), "fmi2GetReal");
}

void Fmu2Instance::DoStep(double t, double h) {
  Check(f_->do_step(component_, t, h, fmi2False),
        fmt::format("fmi2DoStep(t = {} s, h = {} s)", t, h));
}

void Fmu2Instance::SnapshotState() {
  Check(f_->get_state(component_, &snapshot_), "fmi2GetFMUstate");
}

void Fmu2Instance::RestoreSnapshot() {
  Check(f_->set_state(component_, snapshot_), "fmi2SetFMUstate");
}

std::string Fmu2Instance::SerializeSnapshot() {
  size_t size = 0;
  Check(f_->serialized_size(component_, snapshot_, &size), "fmi2SerializedFMUstateSize");
  std::string bytes(size, '\0');
  Check(f_->serialize(component_, snapshot_, bytes.data(), size), "fmi2SerializeFMUstate");
  return bytes;
}

void Fmu2Instance::DeserializeIntoSnapshot(const std::string& bytes) {
  if (snapshot_ != nullptr) {
    Check(f_->free_state(component_, &snapshot_), "fmi2FreeFMUstate");
    snapshot_ = nullptr;
  }
  Check(f_->deserialize(component_, bytes.data(), bytes.size(), &snapshot_),
        "fmi2DeSerializeFMUstate");
}

}  // namespace hybridtest::fmi
