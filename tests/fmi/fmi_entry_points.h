#pragma once
// What a strict FMI importer looks up when it loads an FMU (issue 48): every function the
// standard's header declares for the interfaces the description declares. The lists below
// are written from the standards' text (FMI 2.0.x fmi2Functions.h, sections 2.1, 3.2, 4.2;
// FMI 3.0 fmi3Functions.h, sections 2.3, 3.2, 4.2, 5.2), not from any binary of ours.
#include <dlfcn.h>
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "hybridtest/fmi/fmu_archive.h"
#include "hybridtest/fmi/model_description.h"
#include "support/temp_dir.h"

namespace hybridtest::fmi::test {

// FMI 2.0: for every interface (25), model exchange (10), co-simulation (9).
inline const std::vector<std::string> kFmi2Common{
    "fmi2GetTypesPlatform", "fmi2GetVersion", "fmi2SetDebugLogging", "fmi2Instantiate",
    "fmi2FreeInstance", "fmi2SetupExperiment", "fmi2EnterInitializationMode",
    "fmi2ExitInitializationMode", "fmi2Terminate", "fmi2Reset", "fmi2GetReal", "fmi2GetInteger",
    "fmi2GetBoolean", "fmi2GetString", "fmi2SetReal", "fmi2SetInteger", "fmi2SetBoolean",
    "fmi2SetString", "fmi2GetFMUstate", "fmi2SetFMUstate", "fmi2FreeFMUstate",
    "fmi2SerializedFMUstateSize", "fmi2SerializeFMUstate", "fmi2DeSerializeFMUstate",
    "fmi2GetDirectionalDerivative"};
inline const std::vector<std::string> kFmi2ModelExchange{
    "fmi2EnterEventMode", "fmi2NewDiscreteStates", "fmi2EnterContinuousTimeMode",
    "fmi2CompletedIntegratorStep", "fmi2SetTime", "fmi2SetContinuousStates",
    "fmi2GetDerivatives", "fmi2GetEventIndicators", "fmi2GetContinuousStates",
    "fmi2GetNominalsOfContinuousStates"};
inline const std::vector<std::string> kFmi2CoSimulation{
    "fmi2SetRealInputDerivatives", "fmi2GetRealOutputDerivatives", "fmi2DoStep",
    "fmi2CancelStep", "fmi2GetStatus", "fmi2GetRealStatus", "fmi2GetIntegerStatus",
    "fmi2GetBooleanStatus", "fmi2GetStringStatus"};

// FMI 3.0: for every interface (61), model exchange (10), co-simulation (3), scheduled
// execution (1).
inline const std::vector<std::string> kFmi3Common{
    "fmi3GetVersion", "fmi3SetDebugLogging", "fmi3InstantiateModelExchange",
    "fmi3InstantiateCoSimulation", "fmi3InstantiateScheduledExecution", "fmi3FreeInstance",
    "fmi3EnterInitializationMode", "fmi3ExitInitializationMode", "fmi3EnterEventMode",
    "fmi3Terminate", "fmi3Reset",
    "fmi3GetFloat32", "fmi3GetFloat64", "fmi3GetInt8", "fmi3GetUInt8", "fmi3GetInt16",
    "fmi3GetUInt16", "fmi3GetInt32", "fmi3GetUInt32", "fmi3GetInt64", "fmi3GetUInt64",
    "fmi3GetBoolean", "fmi3GetString", "fmi3GetBinary", "fmi3GetClock",
    "fmi3SetFloat32", "fmi3SetFloat64", "fmi3SetInt8", "fmi3SetUInt8", "fmi3SetInt16",
    "fmi3SetUInt16", "fmi3SetInt32", "fmi3SetUInt32", "fmi3SetInt64", "fmi3SetUInt64",
    "fmi3SetBoolean", "fmi3SetString", "fmi3SetBinary", "fmi3SetClock",
    "fmi3GetNumberOfVariableDependencies", "fmi3GetVariableDependencies",
    "fmi3GetFMUState", "fmi3SetFMUState", "fmi3FreeFMUState", "fmi3SerializedFMUStateSize",
    "fmi3SerializeFMUState", "fmi3DeserializeFMUState",
    "fmi3GetDirectionalDerivative", "fmi3GetAdjointDerivative",
    "fmi3EnterConfigurationMode", "fmi3ExitConfigurationMode",
    "fmi3GetIntervalDecimal", "fmi3GetIntervalFraction", "fmi3GetShiftDecimal",
    "fmi3GetShiftFraction", "fmi3SetIntervalDecimal", "fmi3SetIntervalFraction",
    "fmi3SetShiftDecimal", "fmi3SetShiftFraction", "fmi3EvaluateDiscreteStates",
    "fmi3UpdateDiscreteStates"};
inline const std::vector<std::string> kFmi3ModelExchange{
    "fmi3EnterContinuousTimeMode", "fmi3CompletedIntegratorStep", "fmi3SetTime",
    "fmi3SetContinuousStates", "fmi3GetContinuousStateDerivatives", "fmi3GetEventIndicators",
    "fmi3GetContinuousStates", "fmi3GetNominalsOfContinuousStates",
    "fmi3GetNumberOfEventIndicators", "fmi3GetNumberOfContinuousStates"};
inline const std::vector<std::string> kFmi3CoSimulation{"fmi3EnterStepMode",
                                                        "fmi3GetOutputDerivatives", "fmi3DoStep"};
inline const std::vector<std::string> kFmi3ScheduledExecution{"fmi3ActivateModelPartition"};

// The functions a strict importer requires of the FMU at `fmu` (its description's version and
// interfaces), and those of them its binary does not export (dlopen + dlsym). Returns the
// required count; `missing` gets the absent names.
inline int RequiredEntryPoints(const std::string& fmu, std::vector<std::string>& missing) {
  const std::string xml = ReadMember(fmu, "modelDescription.xml");
  const ModelDescription md = ParseModelDescription(xml, fmu);
  const bool v3 = md.is_fmi3();
  std::vector<std::string> required = v3 ? kFmi3Common : kFmi2Common;
  const auto add = [&](const char* element, const std::vector<std::string>& names) {
    if (xml.find(element) != std::string::npos) required.insert(required.end(), names.begin(), names.end());
  };
  add("<CoSimulation", v3 ? kFmi3CoSimulation : kFmi2CoSimulation);
  add("<ModelExchange", v3 ? kFmi3ModelExchange : kFmi2ModelExchange);
  if (v3) add("<ScheduledExecution", kFmi3ScheduledExecution);
  const std::string member = std::string("binaries/") + (v3 ? "x86_64-linux/" : "linux64/") +
                             md.model_identifier + ".so";
  static const auto dir = test_support::FreshTempDir("fmi_entry_points");
  static int count = 0;
  const auto so = dir / (std::to_string(count++) + "_" + md.model_identifier + ".so");
  {
    std::ofstream out(so, std::ios::binary);
    out << ReadMember(fmu, member);
  }
  void* handle = dlopen(so.c_str(), RTLD_NOW | RTLD_LOCAL);
  EXPECT_NE(handle, nullptr) << fmu << ": " << dlerror();
  if (handle == nullptr) return 0;
  for (const auto& name : required) {
    if (dlsym(handle, name.c_str()) == nullptr) missing.push_back(name);
  }
  dlclose(handle);
  return static_cast<int>(required.size());
}

// EXPECTs that the FMU at `fmu` exports every function its description requires.
inline void ExpectEveryEntryPoint(const std::string& fmu) {
  std::vector<std::string> missing;
  const int required = RequiredEntryPoints(fmu, missing);
  EXPECT_GT(required, 0) << fmu;
  std::string names;
  for (const auto& n : missing) names += " " + n;
  EXPECT_TRUE(missing.empty()) << fmu << " misses " << missing.size() << " of " << required
                               << " functions a strict importer requires:" << names;
}

}  // namespace hybridtest::fmi::test
