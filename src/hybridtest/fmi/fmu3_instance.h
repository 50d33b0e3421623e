#pragma once
// An FMI 3.0 co-simulation FMU unpacked in a folder: binaries/x86_64-linux/<id>.so loaded,
// its functions found by name (fmi3_api.h), the instance made and driven
// (fmi3InstantiateCoSimulation without event mode or early return, parameters,
// fmi3EnterInitializationMode, fmi3ExitInitializationMode; fmi3SetFloat64, fmi3DoStep,
// fmi3GetFloat64; fmi3Get/SetFMUState). An FMU that asks to terminate in fmi3DoStep is a
// TransferError.
#include <memory>
#include <string>

#include "hybridtest/fmi/fmi3_api.h"
#include "hybridtest/fmi/fmu_instance.h"

namespace hybridtest::fmi {

class Fmu3Instance final : public FmuInstance {
 public:
  Fmu3Instance(const std::string& dir, const ModelDescription& md, std::string fmu,
               std::string instance_name, LogSink log);
  ~Fmu3Instance() override;

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
  static void Logger(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category,
                     fmi3String message);
  template <typename F>
  F* Fn(const char* name, bool required = true) {
    return reinterpret_cast<F*>(Symbol(name, required));
  }

  std::unique_ptr<Functions> f_;
  fmi3Instance instance_ = nullptr;
  fmi3FMUState snapshot_ = nullptr;
  bool initialized_ = false;
};

}  // namespace hybridtest::fmi
