#pragma once
// ParameterSet: the named, documented physical parameters of a built-in model, in the order
// they are declared. Config overrides are applied by name; the resolved set is what the
// journal's sidecar and the report print.
#include <string>
#include <string_view>
#include <vector>

namespace hybridtest::models {

struct Parameter {
  std::string name;         // "k_b", "blade1.k_b"
  double value = 0.0;       // SI
  std::string unit;         // "N/m"
  std::string description;  // "blade stiffness"
};

class ParameterSet {
 public:
  void Add(std::string name, double value, std::string unit, std::string description);
  bool Has(std::string_view name) const;
  // Throws ConfigError naming the parameter if it is unknown.
  double Get(std::string_view name) const;
  // Overrides a value. `where` locates the override for error messages (e.g.
  // "config.yaml: model.parameters.k_b"). Throws ConfigError if the name is unknown (listing
  // the known names) or the value is not finite.
  void Set(std::string_view name, double value, std::string_view where);
  const std::vector<Parameter>& all() const { return parameters_; }

 private:
  std::vector<Parameter> parameters_;
};

}  // namespace hybridtest::models
