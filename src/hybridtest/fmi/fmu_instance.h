#pragma once
// One instance of a co-simulation FMU, whatever its FMI version (fmu2_instance.h,
// fmu3_instance.h), as FmuSubstructure drives it. The base loads the FMU's shared library
// (dlopen), keeps its log and turns a failing status into a TransferError naming the FMU, the
// call and the FMU's last log lines (an FMU error stops the run like a lost bench).
//
// The FMU's log goes to a sink; by default to stderr, one line per message:
// "fmu <instance>: <status> [<category>] <message>" (the run's log).
#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "hybridtest/fmi/model_description.h"

namespace hybridtest::fmi {

// Where the FMU's log lines go (one finished line each).
using LogSink = std::function<void(const std::string& line)>;
LogSink StderrLog();

class FmuInstance {
 public:
  virtual ~FmuInstance();
  FmuInstance(const FmuInstance&) = delete;
  FmuInstance& operator=(const FmuInstance&) = delete;

  // A parameter value: a Real's value, or an Integer's / Boolean's (0 or 1).
  struct Value {
    const ModelVariable* variable = nullptr;
    double value = 0.0;
  };
  // Sets up the experiment at `start_time` [s], sets the parameters, and initializes.
  virtual void Initialize(double start_time, const std::vector<Value>& parameters) = 0;
  virtual void SetReal(const std::vector<unsigned>& vr, const std::vector<double>& values) = 0;
  virtual void GetReal(const std::vector<unsigned>& vr, std::vector<double>& values) = 0;
  // One communication step from `t` [s] of `h` > 0 [s].
  virtual void DoStep(double t, double h) = 0;
  // The FMU state (needs the get/set capability): one snapshot kept in the instance.
  virtual void SnapshotState() = 0;    // get the FMU state into the snapshot
  virtual void RestoreSnapshot() = 0;  // set the FMU state from it
  // The snapshot as bytes (needs the serialize capability), and back into the snapshot.
  virtual std::string SerializeSnapshot() = 0;
  virtual void DeserializeIntoSnapshot(const std::string& bytes) = 0;

  const std::string& fmu() const { return fmu_; }
  // The FMU's last log lines (at most 8), newest last.
  const std::deque<std::string>& recent_log() const { return recent_; }

 protected:
  // Loads `so` (`binary` names it in messages, e.g. "binaries/linux64/spring.so"). Throws
  // ConfigError if the file is missing or cannot be loaded.
  FmuInstance(const std::string& so, const std::string& binary, std::string fmu,
              std::string instance_name, LogSink log);
  // The function `name` of the library; nullptr if absent and not `required`, else
  // ConfigError.
  void* Symbol(const char* name, bool required) const;
  // Records one log message of the FMU.
  void Log(int status, const char* category, const std::string& text);
  // Throws TransferError unless `status` is OK (0) or Warning (1); marks the instance failed
  // (Error, Discard) or fatal (Fatal, after which nothing may be called).
  void Check(int status, const std::string& call);
  // The recent log lines for a message ("" if none).
  std::string RecentLines() const;

  std::string fmu_;
  std::string instance_name_;
  int fmi_version_ = 2;  // 2 or 3, for messages ("fmi2Error")
  bool fatal_ = false;
  bool failed_ = false;

 private:
  LogSink log_;
  void* library_ = nullptr;
  std::deque<std::string> recent_;
};

// The instance of the FMU unpacked in `dir`, for its FMI version (2.0 or 3.0). Throws
// ConfigError (binary, functions), TransferError (instantiation).
std::unique_ptr<FmuInstance> LoadFmu(const std::string& dir, const ModelDescription& md,
                                     const std::string& fmu, const std::string& instance_name,
                                     LogSink log);

// The platform folder of this machine's binaries: "linux64" (FMI 2), "x86_64-linux" (FMI 3).
const char* PlatformFolder(const ModelDescription& md);

}  // namespace hybridtest::fmi
