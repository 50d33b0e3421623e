// See fmu3_instance.h.
#include "hybridtest/fmi/fmu3_instance.h"

#include <fmt/core.h>

#include <cmath>
#include <filesystem>

#include "hybridtest/common/error.h"

namespace hybridtest::fmi {
namespace {

std::string SharedObject(const std::string& dir, const ModelDescription& md) {
  return (std::filesystem::path(dir) / "binaries" / "x86_64-linux" / (md.model_identifier + ".so"))
      .string();
}

}  // namespace

struct Fmu3Instance::Functions {
  fmi3InstantiateCoSimulationTYPE* instantiate = nullptr;
  fmi3FreeInstanceTYPE* free_instance = nullptr;
  fmi3EnterInitializationModeTYPE* enter_initialization = nullptr;
  fmi3ExitInitializationModeTYPE* exit_initialization = nullptr;
  fmi3TerminateTYPE* terminate = nullptr;
  fmi3GetFloat64TYPE* get_float64 = nullptr;
  fmi3SetFloat64TYPE* set_float64 = nullptr;
  fmi3SetInt32TYPE* set_int32 = nullptr;
  fmi3SetBooleanTYPE* set_boolean = nullptr;
  fmi3DoStepTYPE* do_step = nullptr;
  fmi3GetFMUStateTYPE* get_state = nullptr;
  fmi3SetFMUStateTYPE* set_state = nullptr;
  fmi3FreeFMUStateTYPE* free_state = nullptr;
  fmi3SerializedFMUStateSizeTYPE* serialized_size = nullptr;
  fmi3SerializeFMUStateTYPE* serialize = nullptr;
  fmi3DeserializeFMUStateTYPE* deserialize = nullptr;
};

Fmu3Instance::Fmu3Instance(const std::string& dir, const ModelDescription& md, std::string fmu,
                           std::string instance_name, LogSink log)
    : FmuInstance(SharedObject(dir, md), "binaries/x86_64-linux/" + md.model_identifier + ".so",
                  std::move(fmu), std::move(instance_name), std::move(log)),
      f_(std::make_unique<Functions>()) {
  fmi_version_ = 3;
  f_->instantiate = Fn<fmi3InstantiateCoSimulationTYPE>("fmi3InstantiateCoSimulation");
  f_->free_instance = Fn<fmi3FreeInstanceTYPE>("fmi3FreeInstance");
  f_->enter_initialization = Fn<fmi3EnterInitializationModeTYPE>("fmi3EnterInitializationMode");
  f_->exit_initialization = Fn<fmi3ExitInitializationModeTYPE>("fmi3ExitInitializationMode");
  f_->terminate = Fn<fmi3TerminateTYPE>("fmi3Terminate");
  f_->get_float64 = Fn<fmi3GetFloat64TYPE>("fmi3GetFloat64");
  f_->set_float64 = Fn<fmi3SetFloat64TYPE>("fmi3SetFloat64");
  f_->set_int32 = Fn<fmi3SetInt32TYPE>("fmi3SetInt32");
  f_->set_boolean = Fn<fmi3SetBooleanTYPE>("fmi3SetBoolean");
  f_->do_step = Fn<fmi3DoStepTYPE>("fmi3DoStep");
  const bool state = md.can_get_and_set_state;
  f_->get_state = Fn<fmi3GetFMUStateTYPE>("fmi3GetFMUState", state);
  f_->set_state = Fn<fmi3SetFMUStateTYPE>("fmi3SetFMUState", state);
  f_->free_state = Fn<fmi3FreeFMUStateTYPE>("fmi3FreeFMUState", state);
  const bool serial = md.can_serialize_state;
  f_->serialized_size = Fn<fmi3SerializedFMUStateSizeTYPE>("fmi3SerializedFMUStateSize", serial);
  f_->serialize = Fn<fmi3SerializeFMUStateTYPE>("fmi3SerializeFMUState", serial);
  f_->deserialize = Fn<fmi3DeserializeFMUStateTYPE>("fmi3DeserializeFMUState", serial);
  // FMI 3.0 section 2.2.4: the resource path is a directory path ending in a separator.
  const std::string resources =
      (std::filesystem::absolute(std::filesystem::path(dir)) / "resources").lexically_normal().string() + "/";
  instance_ = f_->instantiate(instance_name_.c_str(), md.guid.c_str(), resources.c_str(), false,
                              false, false, false, nullptr, 0, this, &Logger, nullptr);
  if (instance_ == nullptr) {
    const std::string lines = RecentLines();
    throw TransferError(fmt::format("{}: fmi3InstantiateCoSimulation failed (instantiationToken "
                                    "{}){}", fmu_, md.guid,
                                    lines.empty() ? " and the FMU logged nothing" : lines));
  }
}

Fmu3Instance::~Fmu3Instance() {
  if (instance_ == nullptr || fatal_) return;
  if (snapshot_ != nullptr && !failed_) f_->free_state(instance_, &snapshot_);
  if (initialized_ && !failed_) f_->terminate(instance_);
  f_->free_instance(instance_);
}

void Fmu3Instance::Logger(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category,
                          fmi3String message) {
  if (env != nullptr) {
    static_cast<Fmu3Instance*>(env)->Log(status, category, message != nullptr ? message : "");
  }
}

void Fmu3Instance::Initialize(double start_time, const std::vector<Value>& parameters) {
  // FMI 3: parameters are set in the Instantiated state, before initialization mode.
  for (const Value& p : parameters) {
    const fmi3ValueReference vr = p.variable->value_reference;
    const std::string call = "setting parameter " + p.variable->name;
    if (p.variable->type == "Float64") {
      Check(f_->set_float64(instance_, &vr, 1, &p.value, 1), call);
    } else if (p.variable->type == "Boolean") {
      const fmi3Boolean b = p.value != 0.0;
      Check(f_->set_boolean(instance_, &vr, 1, &b, 1), call);
    } else {
      const auto i = static_cast<fmi3Int32>(std::lround(p.value));
      Check(f_->set_int32(instance_, &vr, 1, &i, 1), call);
    }
  }
  Check(f_->enter_initialization(instance_, false, 0.0, start_time, false, 0.0),
        "fmi3EnterInitializationMode");
  Check(f_->exit_initialization(instance_), "fmi3ExitInitializationMode");
  initialized_ = true;
}

void Fmu3Instance::SetReal(const std::vector<unsigned>& vr, const std::vector<double>& values) {
  Check(f_->set_float64(instance_, vr.data(), vr.size(), values.data(), values.size()),
        "fmi3SetFloat64");
}

void Fmu3Instance::GetReal(const std::vector<unsigned>& vr, std::vector<double>& values) {
  values.resize(vr.size());
  Check(f_->get_float64(instance_, vr.data(), vr.size(), values.data(), values.size()),
        "fmi3GetFloat64");
}

void Fmu3Instance::DoStep(double t, double h) {
  fmi3Boolean event = false, terminate = false, early = false;
  fmi3Float64 last = t;
  const std::string call = fmt::format("fmi3DoStep(t = {} s, h = {} s)", t, h);
  Check(f_->do_step(instance_, t, h, false, &event, &terminate, &early, &last), call);
  if (terminate) {
    failed_ = true;
    throw TransferError(fmt::format("{}: {} asked to terminate the simulation at {} s{}", fmu_,
                                    call, last, RecentLines()));
  }
}

void Fmu3Instance::SnapshotState() {
  Check(f_->get_state(instance_, &snapshot_), "fmi3GetFMUState");
}

void Fmu3Instance::RestoreSnapshot() {
  Check(f_->set_state(instance_, snapshot_), "fmi3SetFMUState");
}

std::string Fmu3Instance::SerializeSnapshot() {
  size_t size = 0;
  Check(f_->serialized_size(instance_, snapshot_, &size), "fmi3SerializedFMUStateSize");
  std::string bytes(size, '\0');
  Check(f_->serialize(instance_, snapshot_, reinterpret_cast<fmi3Byte*>(bytes.data()), size),
        "fmi3SerializeFMUState");
  return bytes;
}

void Fmu3Instance::DeserializeIntoSnapshot(const std::string& bytes) {
  if (snapshot_ != nullptr) {
    Check(f_->free_state(instance_, &snapshot_), "fmi3FreeFMUState");
    snapshot_ = nullptr;
  }
  Check(f_->deserialize(instance_, reinterpret_cast<const fmi3Byte*>(bytes.data()), bytes.size(),
                        &snapshot_),
        "fmi3DeserializeFMUState");
}

}  // namespace hybridtest::fmi
