// See model_checks.h.
#include "hybridtest/models/model_checks.h"

#include <fmt/core.h>

#include "hybridtest/common/error.h"

namespace hybridtest::models {

namespace {
const Parameter& Find(const ParameterSet& p, const std::string& name) {
  for (const Parameter& param : p.all()) {
    if (param.name == name) return param;
  }
  throw ConfigError(fmt::format("unknown model parameter '{}'", name));
}
}  // namespace

void RequirePositive(const ParameterSet& p, const std::string& name) {
  const Parameter& param = Find(p, name);
  if (!(param.value > 0.0)) {
    throw ConfigError(fmt::format("model.parameters.{} = {}: expected a positive value in {} ({})",
                                  name, param.value, param.unit, param.description));
  }
}

void RequireNonNegative(const ParameterSet& p, const std::string& name) {
  const Parameter& param = Find(p, name);
  if (!(param.value >= 0.0)) {
    throw ConfigError(fmt::format("model.parameters.{} = {}: expected a value ≥ 0 in {} ({})",
                                  name, param.value, param.unit, param.description));
  }
}

}  // namespace hybridtest::models
