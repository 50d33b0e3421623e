#pragma once
// Parameter checks shared by the built-in models.
#include <string>

#include "hybridtest/models/parameters.h"

namespace hybridtest::models {

// Throws ConfigError "model.parameters.<name> = <v>: expected a positive value in <unit>".
void RequirePositive(const ParameterSet& p, const std::string& name);
void RequireNonNegative(const ParameterSet& p, const std::string& name);

}  // namespace hybridtest::models
