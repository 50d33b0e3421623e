// The Modbus test controller's start-up message names the right cause when pymodbus cannot be
// imported: installed for Debian's interpreter but invisible to this one is not "missing".
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "support/run_command.h"

namespace hybridtest {
namespace {

TEST(ModbusServerScript, InterpreterWithoutDebiansPackagesIsToldToUseDebians) {
  if (!std::filesystem::is_directory("/usr/lib/python3/dist-packages/pymodbus")) {
    GTEST_SKIP() << "python3-pymodbus is not installed";
  }
  // -S: no site packages, like an interpreter that is not Debian's.
  const auto [status, out] = testing::RunCommand(
      std::string(HYBRIDTEST_PYTHON) + " -S " + HYBRIDTEST_MODBUS_PY + " --help");
  EXPECT_EQ(status, 3) << out;
  EXPECT_NE(out.find("python3-pymodbus is installed"), std::string::npos) << out;
  EXPECT_NE(out.find("/usr/bin/python3 "), std::string::npos) << out;
  EXPECT_EQ(out.find("install python3-pymodbus"), std::string::npos) << out;
}

TEST(ModbusServerScript, DebiansInterpreterStarts) {
  const auto [status, out] = testing::RunCommand(std::string(HYBRIDTEST_PYTHON) + " " +
                                                 HYBRIDTEST_MODBUS_PY + " --help");
  EXPECT_EQ(status, 0) << out;
  EXPECT_NE(out.find("usage:"), std::string::npos) << out;
}

}  // namespace
}  // namespace hybridtest
