#pragma once
// An FMI 2.0 co-simulation FMU unpacked in a folder: binaries/linux64/<modelIdentifier>.so
// loaded, its functions found by name (fmi2_api.h), the instance made and driven
// (fmi2Instantiate, fmi2SetupExperiment, parameters, fmi2EnterInitializationMode,
// fmi2ExitInitializationMode; fmi2SetReal, fmi2DoStep, fmi2GetReal; fmi2Get/SetFMUstate).
#include <memory>
#include <string>

#include "hybridtest/fmi/fmi2_api.h"
#include "hybridtest/fmi/fmu_instance.h"

namespace hybridtest::fmi {

class Fmu2Instance final : public FmuInstance {
 public:
  // Throws ConfigError for a missing binary or function, TransferError if instantiation fails.
  Fmu2Instance(const std::string& dir, const ModelDescription& md, std::string fmu,
               std::string instance_name, LogSink log);
  ~Fmu2Instance() override;

  void Initialize(double start_time, const std::vector<Value>& parameters) override;
  void SetReal(const std::vector<unsigned>& vr, const std::vector<double>& values) override;
  void GetReal(const std::vector<unsigned>& vr, std::vector<double>& values) override;
  void DoStep(double t, double h) override;
  void SnapshotState() override;
  void RestoreSnapshot() override;
  std::string SerializeSnapshot() override;
  void DeserializeIntoSnapshot(const std::string& bytes) override;

 private:
  struct Functions;
  static void Logger(fmi2ComponentEnvironment env, fmi2String instance, fmi2Status status,
                     fmi2String category, fmi2String message, ...);
  template <typename F>
  F* Fn(const char* name, bool required = true) {
    return reinterpret_cast<F*>(Symbol(name, required));
  }

  std::unique_ptr<Functions> f_;
  std::unique_ptr<fmi2CallbackFunctions> callbacks_;
  fmi2Component component_ = nullptr;
  fmi2FMUstate snapshot_ = nullptr;
  bool initialized_ = false;
};

}  // namespace hybridtest::fmi
