// Issue 48: every FMU the project builds (the test FMUs of tests/fmi/fmus/, the examples of
// examples/fmi/; the exported rotor in fmu_export_test.cc) exports every function the FMI
// standard's header declares for the interfaces its description declares, as strict importers
// (FMIL, OMSimulator) require at load; those the FMU does not support return Error and say
// why in the importer's log (the shared entry points, src/hybridtest/fmi/fmu_entry.c).
#include <dlfcn.h>
#include <gtest/gtest.h>

#include <cstdarg>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "fmi/fmi_entry_points.h"
#include "fmi/fmi_test_support.h"
#include "hybridtest/fmi/fmi2_api.h"
#include "hybridtest/fmi/fmi3_api.h"

namespace hybridtest::fmi::test {
namespace {

TEST(FmuEntryPoints, EveryTestAndExampleFmuExportsWhatItsInterfacesRequire) {
  for (const char* id : {"spring", "maxwell", "maxwell_nostate", "maxwell3", "coupled_spring"}) {
    ExpectEveryEntryPoint(TestFmu(id));
  }
  for (const char* id : {"spring", "bouc_wen"}) {
    ExpectEveryEntryPoint(std::string(HYBRIDTEST_EXAMPLE_FMU_DIR) + "/" + id + ".fmu");
  }
  // The lists are the standard's: 44 functions of FMI 2.0, 75 of FMI 3.0.
  EXPECT_EQ(kFmi2Common.size() + kFmi2ModelExchange.size() + kFmi2CoSimulation.size(), 44u);
  EXPECT_EQ(kFmi3Common.size() + kFmi3ModelExchange.size() + kFmi3CoSimulation.size() +
                kFmi3ScheduledExecution.size(),
            75u);
}

// A check that can fail: an FMU whose binary lacks functions is reported, by name.
TEST(FmuEntryPoints, AnFmuWithoutThemIsReportedByName) {
  // An FMI 2.0 co-simulation FMU requires 25 + 9 functions; one whose binary is a library
  // without any (libm in place of maxwell.so) misses every one.
  const std::string fmu = TestFmu("maxwell");
  std::vector<std::string> missing;
  EXPECT_EQ(RequiredEntryPoints(fmu, missing), 25 + 9);
  EXPECT_TRUE(missing.empty());
  std::ifstream libm("/lib/x86_64-linux-gnu/libm.so.6", std::ios::binary);
  ASSERT_TRUE(libm.good());
  std::ostringstream read;
  read << libm.rdbuf();
  const std::string bytes = read.str();
  const std::string empty =
      (test_support::FreshTempDir("fmi_entry_missing") / "no_functions.fmu").string();
  WriteArchive(empty, {{"modelDescription.xml", ReadMember(fmu, "modelDescription.xml")},
                       {"binaries/linux64/maxwell.so", bytes}});
  missing.clear();
  EXPECT_EQ(RequiredEntryPoints(empty, missing), 34);
  EXPECT_EQ(missing.size(), 34u);
}

std::vector<std::string> g_log;
void Log3(fmi3InstanceEnvironment, fmi3Status, fmi3String, fmi3String message) {
  g_log.emplace_back(message);
}
void Log2(fmi2ComponentEnvironment, fmi2String, fmi2Status, fmi2String, fmi2String format, ...) {
  char text[1024];
  va_list args;
  va_start(args, format);
  std::vsnprintf(text, sizeof text, format, args);
  va_end(args);
  g_log.emplace_back(text);
}

template <typename F>
F* Fn(void* handle, const char* name) {
  return reinterpret_cast<F*>(dlsym(handle, name));
}

TEST(FmuEntryPoints, UnsupportedFunctionsReturnErrorAndLogWhy) {
  const auto dir = test_support::FreshTempDir("fmi_entry_unsupported");
  ExtractArchive(TestFmu("maxwell3"), (dir / "m3").string());
  void* h = dlopen((dir / "m3/binaries/x86_64-linux/maxwell3.so").c_str(), RTLD_NOW | RTLD_LOCAL);
  ASSERT_NE(h, nullptr) << dlerror();
  g_log.clear();
  using Me = fmi3Instance(fmi3String, fmi3String, fmi3String, fmi3Boolean, fmi3Boolean,
                          fmi3InstanceEnvironment, fmi3LogMessageCallback);
  EXPECT_EQ(Fn<Me>(h, "fmi3InstantiateModelExchange")("m", "{hybridtest-test-maxwell}", "",
                                                       false, false, nullptr, Log3),
            nullptr);
  ASSERT_EQ(g_log.size(), 1u);
  EXPECT_NE(g_log[0].find("co-simulation only"), std::string::npos) << g_log[0];
  fmi3Instance in = Fn<fmi3InstantiateCoSimulationTYPE>(h, "fmi3InstantiateCoSimulation")(
      "m", "{hybridtest-test-maxwell}", "", false, false, false, false, nullptr, 0, nullptr, Log3,
      nullptr);
  ASSERT_NE(in, nullptr);
  const fmi3ValueReference vr[] = {1};
  double value = 0.0;
  const fmi3Int32 order[] = {1};
  using OutputDerivatives = fmi3Status(fmi3Instance, const fmi3ValueReference[], size_t,
                                       const fmi3Int32[], fmi3Float64[], size_t);
  EXPECT_EQ(Fn<OutputDerivatives>(h, "fmi3GetOutputDerivatives")(in, vr, 1, order, &value, 1),
            fmi3Error);
  EXPECT_NE(g_log.back().find("fmi3GetOutputDerivatives is not supported: maxOutputDerivativeOrder"),
            std::string::npos) << g_log.back();
  int32_t i = 0;
  using GetInt32 = fmi3Status(fmi3Instance, const fmi3ValueReference[], size_t, int32_t[], size_t);
  EXPECT_EQ(Fn<GetInt32>(h, "fmi3GetInt32")(in, vr, 0, &i, 0), fmi3OK);  // no value asked
  EXPECT_EQ(Fn<GetInt32>(h, "fmi3GetInt32")(in, vr, 1, &i, 1), fmi3Error);
  EXPECT_NE(g_log.back().find("scalar Float64"), std::string::npos) << g_log.back();
  EXPECT_EQ(Fn<fmi3ExitInitializationModeTYPE>(h, "fmi3EnterEventMode")(in), fmi3Error);
  EXPECT_NE(g_log.back().find("event mode"), std::string::npos) << g_log.back();
  Fn<fmi3FreeInstanceTYPE>(h, "fmi3FreeInstance")(in);
  dlclose(h);

  // FMI 2: the example spring has no state; asking for it is an error that says so.
  ExtractArchive(std::string(HYBRIDTEST_EXAMPLE_FMU_DIR) + "/spring.fmu", (dir / "s").string());
  h = dlopen((dir / "s/binaries/linux64/spring.so").c_str(), RTLD_NOW | RTLD_LOCAL);
  ASSERT_NE(h, nullptr) << dlerror();
  const fmi2CallbackFunctions callbacks{Log2, nullptr, nullptr, nullptr, nullptr};
  fmi2Component c = Fn<fmi2InstantiateTYPE>(h, "fmi2Instantiate")(
      "s", fmi2CoSimulation, "{hybridtest-example-spring}", "", &callbacks, 0, 0);
  ASSERT_NE(c, nullptr);
  fmi2FMUstate state = nullptr;
  EXPECT_EQ(Fn<fmi2GetFMUstateTYPE>(h, "fmi2GetFMUstate")(c, &state), fmi2Error);
  EXPECT_NE(g_log.back().find("fmi2GetFMUstate is not supported: canGetAndSetFMUState is false"),
            std::string::npos) << g_log.back();
  fmi2String text = nullptr;
  using GetString = fmi2Status(fmi2Component, const fmi2ValueReference[], size_t, fmi2String[]);
  const fmi2ValueReference k[] = {2};
  EXPECT_EQ(Fn<GetString>(h, "fmi2GetString")(c, k, 1, &text), fmi2Error);
  EXPECT_NE(g_log.back().find("every variable of this FMU is a Real"), std::string::npos)
      << g_log.back();
  EXPECT_EQ(Fn<fmi2InstantiateTYPE>(h, "fmi2Instantiate")(
                "s", fmi2ModelExchange, "{hybridtest-example-spring}", "", &callbacks, 0, 0),
            nullptr);
  Fn<fmi2FreeInstanceTYPE>(h, "fmi2FreeInstance")(c);
  dlclose(h);
}

}  // namespace
}  // namespace hybridtest::fmi::test
