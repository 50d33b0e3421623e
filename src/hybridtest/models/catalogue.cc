// See catalogue.h.
#include "hybridtest/models/catalogue.h"

#include <fmt/core.h>

#include "hybridtest/common/error.h"
#include "hybridtest/models/double_pendulum.h"
#include "hybridtest/models/rotor.h"
#include "hybridtest/models/spinning_top.h"

namespace hybridtest::models {

std::vector<std::string> ModelNames() { return {"rotor", "double_pendulum", "spinning_top"}; }

namespace {
[[noreturn]] void UnknownModel(const std::string& name) {
  throw ConfigError(fmt::format("unknown model '{}'; expected one of: rotor, double_pendulum, "
                                "spinning_top (see `hybridtest models`)", name));
}
}  // namespace

ParameterSet DefaultParameters(const std::string& name, int blades) {
  if (name == "rotor") return RotorDefaultParameters(blades);
  if (name == "double_pendulum") return DoublePendulumDefaultParameters();
  if (name == "spinning_top") return SpinningTopDefaultParameters();
  UnknownModel(name);
}

BuiltModel BuildModel(const std::string& name, int blades, const ParameterSet& parameters) {
  if (name == "rotor") return BuildRotor(blades, parameters);
  if (name == "double_pendulum") return BuildDoublePendulum(parameters);
  if (name == "spinning_top") return BuildSpinningTop(parameters);
  UnknownModel(name);
}

}  // namespace hybridtest::models
