#pragma once
// One instance of an FMI 2.0 co-simulation FMU, unpacked in a folder: its shared library
// loaded with dlopen (binaries/linux64/<modelIdentifier>.so), its functions found by name
// (fmi2_api.h), the instance made, set up and driven. Every FMI call's status is checked: a
// warning goes to the log, Discard, Error and Fatal throw TransferError naming the FMU, the
// call and the FMU's last log lines (an FMU error stops the run like a lost bench).
//
// The FMU's log (its logger callback) goes to a sink; by default to stderr, one line per
// message: "fmu <instance>: <status> [<category>] <message>" (the run's log).
#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "hybridtest/fmi/fmi2_api.h"
#include "hybridtest/fmi/model_description.h"

namespace hybridtest::fmi {

// Where the FMU's log lines go (one finished line each).
using LogSink = std::function<void(const std::string& line)>;
LogSink StderrLog();

// The platform folder of FMI 2.0 binaries on this machine ("linux64").
inline constexpr const char* kFmi2Platform = "linux64";

class Fmu2Instance {
 public:
  // Loads `dir`/binaries/linux64/<md.model_identifier>.so and instantiates it for
  // co-simulation as `instance_name`. `fmu` names the FMU file in messages. Throws ConfigError
  // for a missing binary or function, TransferError if instantiation fails.
  Fmu2Instance(const std::string& dir, const ModelDescription& md, std::string fmu,
               std::string instance_name, LogSink log);
  ~Fmu2Instance();
  Fmu2Instance(const Fmu2Instance&) = delete;
  Fmu2Instance& operator=(const Fmu2Instance&) = delete;

  // fmi2SetupExperiment(start), then the parameters (set before initialization), then
  // fmi2EnterInitializationMode / fmi2ExitInitializationMode.
  struct Value {
    const ModelVariable* variable = nullptr;
    double value = 0.0;  // a Real's value, or an Integer's / Boolean's (0 or 1)
  };
  void Initialize(double start_time, const std::vector<Value>& parameters);

  void SetReal(const std::vector<fmi2ValueReference>& vr, const std::vector<double>& values);
  void GetReal(const std::vector<fmi2ValueReference>& vr, std::vector<double>& values);
  // fmi2DoStep(t, h, noSetFMUStatePriorToCurrentPoint = false). `t`: the communication point
  // [s]; `h` > 0 [s].
  void DoStep(double t, double h);

  // The FMU state (needs canGetAndSetFMUstate): one snapshot kept here.
  void SnapshotState();   // fmi2GetFMUstate into the kept snapshot
  void RestoreSnapshot();  // fmi2SetFMUstate from it
  bool has_snapshot() const { return snapshot_ != nullptr; }
  // The kept snapshot as bytes (needs canSerializeFMUstate), and back.
  std::string SerializeSnapshot();
  void DeserializeIntoSnapshot(const std::string& bytes);

  const std::string& fmu() const { return fmu_; }
  // The FMU's last log lines (at most 8), newest last.
  const std::deque<std::string>& recent_log() const { return recent_; }

 private:
  struct Functions;
  static void Logger(fmi2ComponentEnvironment env, fmi2String instance, fmi2Status status,
                     fmi2String category, fmi2String message, ...);
  void LoadAndInstantiate(const std::string& dir, const ModelDescription& md);
  void Check(fmi2Status status, const std::string& call);
  template <typename F>
  F* Symbol(const char* name, bool required);

  std::string fmu_;
  std::string instance_name_;
  LogSink log_;
  void* library_ = nullptr;
  std::unique_ptr<Functions> f_;
  std::unique_ptr<fmi2CallbackFunctions> callbacks_;
  fmi2Component component_ = nullptr;
  fmi2FMUstate snapshot_ = nullptr;
  bool initialized_ = false;
  bool fatal_ = false;   // after fmi2Fatal nothing may be called, not even fmi2FreeInstance
  bool failed_ = false;  // after fmi2Error only fmi2FreeInstance (or fmi2Reset)
  std::deque<std::string> recent_;
};

}  // namespace hybridtest::fmi
