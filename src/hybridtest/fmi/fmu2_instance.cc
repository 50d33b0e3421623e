// See fmu2_instance.h.
#include "hybridtest/fmi/fmu2_instance.h"

#include <fmt/core.h>

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "hybridtest/common/error.h"

namespace hybridtest::fmi {
namespace {

void* Allocate(size_t n, size_t size) { return std::calloc(n, size); }
void Free(void* p) { std::free(p); }

std::string SharedObject(const std::string& dir, const ModelDescription& md) {
  return (std::filesystem::path(dir) / "binaries" / "linux64" / (md.model_identifier + ".so"))
      .string();
}

}  // namespace

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

Fmu2Instance::Fmu2Instance(const std::string& dir, const ModelDescription& md, std::string fmu,
                           std::string instance_name, LogSink log)
    : FmuInstance(SharedObject(dir, md), "binaries/linux64/" + md.model_identifier + ".so",
                  std::move(fmu), std::move(instance_name), std::move(log)),
      f_(std::make_unique<Functions>()) {
  fmi_version_ = 2;
  f_->instantiate = Fn<fmi2InstantiateTYPE>("fmi2Instantiate");
  f_->free_instance = Fn<fmi2FreeInstanceTYPE>("fmi2FreeInstance");
  f_->setup_experiment = Fn<fmi2SetupExperimentTYPE>("fmi2SetupExperiment");
  f_->enter_initialization = Fn<fmi2EnterInitializationModeTYPE>("fmi2EnterInitializationMode");
  f_->exit_initialization = Fn<fmi2ExitInitializationModeTYPE>("fmi2ExitInitializationMode");
  f_->terminate = Fn<fmi2TerminateTYPE>("fmi2Terminate");
  f_->get_real = Fn<fmi2GetRealTYPE>("fmi2GetReal");
  f_->set_real = Fn<fmi2SetRealTYPE>("fmi2SetReal");
  f_->set_integer = Fn<fmi2SetIntegerTYPE>("fmi2SetInteger");
  f_->set_boolean = Fn<fmi2SetBooleanTYPE>("fmi2SetBoolean");
  f_->do_step = Fn<fmi2DoStepTYPE>("fmi2DoStep");
  const bool state = md.can_get_and_set_state;
  f_->get_state = Fn<fmi2GetFMUstateTYPE>("fmi2GetFMUstate", state);
  f_->set_state = Fn<fmi2SetFMUstateTYPE>("fmi2SetFMUstate", state);
  f_->free_state = Fn<fmi2FreeFMUstateTYPE>("fmi2FreeFMUstate", state);
  const bool serial = md.can_serialize_state;
  f_->serialized_size = Fn<fmi2SerializedFMUstateSizeTYPE>("fmi2SerializedFMUstateSize", serial);
  f_->serialize = Fn<fmi2SerializeFMUstateTYPE>("fmi2SerializeFMUstate", serial);
  f_->deserialize = Fn<fmi2DeSerializeFMUstateTYPE>("fmi2DeSerializeFMUstate", serial);

  // FMI 2.0 section 2.1.5: the resource location is a file URI.
  callbacks_.reset(new fmi2CallbackFunctions{&Logger, &Allocate, &Free, nullptr, this});
  const std::string resources =
      "file://" +
      (std::filesystem::absolute(std::filesystem::path(dir)) / "resources").lexically_normal().string();
  component_ = f_->instantiate(instance_name_.c_str(), fmi2CoSimulation, md.guid.c_str(),
                               resources.c_str(), callbacks_.get(), fmi2False, fmi2False);
  if (component_ == nullptr) {
    const std::string lines = RecentLines();
    throw TransferError(fmt::format("{}: fmi2Instantiate failed (guid {}){}", fmu_, md.guid,
                                    lines.empty() ? " and the FMU logged nothing" : lines));
  }
}

Fmu2Instance::~Fmu2Instance() {
  if (component_ == nullptr || fatal_) return;
  if (snapshot_ != nullptr && !failed_) f_->free_state(component_, &snapshot_);
  if (initialized_ && !failed_) f_->terminate(component_);
  f_->free_instance(component_);
}

void Fmu2Instance::Logger(fmi2ComponentEnvironment env, fmi2String /*instance*/,
                          fmi2Status status, fmi2String category, fmi2String message, ...) {
  char text[1024];
  va_list args;
  va_start(args, message);
  std::vsnprintf(text, sizeof text, message != nullptr ? message : "", args);
  va_end(args);
  if (env != nullptr) static_cast<Fmu2Instance*>(env)->Log(status, category, text);
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

void Fmu2Instance::SetReal(const std::vector<unsigned>& vr, const std::vector<double>& values) {
  Check(f_->set_real(component_, vr.data(), vr.size(), values.data()), "fmi2SetReal");
}

void Fmu2Instance::GetReal(const std::vector<unsigned>& vr, std::vector<double>& values) {
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
