// See parameters.h.
#include "hybridtest/models/parameters.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "hybridtest/common/error.h"

namespace hybridtest::models {

void ParameterSet::Add(std::string name, double value, std::string unit, std::string description) {
  parameters_.push_back({std::move(name), value, std::move(unit), std::move(description)});
}

bool ParameterSet::Has(std::string_view name) const {
  return std::any_of(parameters_.begin(), parameters_.end(),
                     [&](const Parameter& p) { return p.name == name; });
}

double ParameterSet::Get(std::string_view name) const {
  for (const Parameter& p : parameters_) {
    if (p.name == name) return p.value;
  }
  throw ConfigError(fmt::format("unknown model parameter '{}'", name));
}

void ParameterSet::Set(std::string_view name, double value, std::string_view where) {
  for (Parameter& p : parameters_) {
    if (p.name != name) continue;
    if (!std::isfinite(value)) {
      throw ConfigError(fmt::format("{} = {}: expected a finite number in {}", where, value,
                                    p.unit));
    }
    p.value = value;
    return;
  }
  std::string known;
  for (const Parameter& p : parameters_) known += (known.empty() ? "" : ", ") + p.name;
  throw ConfigError(fmt::format("{}: unknown parameter '{}' for this model; known parameters: {}",
                                where, name, known));
}

}  // namespace hybridtest::models
