#include "hybridtest/constitutive/parse_law.h"

#include <fmt/format.h>

#include "hybridtest/common/error.h"
#include "hybridtest/constitutive/bouc_wen.h"
#include "hybridtest/constitutive/cantilever.h"
#include "hybridtest/constitutive/linear_spring.h"
#include "hybridtest/constitutive/yaml_fields.h"

namespace hybridtest::constitutive {
namespace {

std::unique_ptr<RestoringForceLaw> ParseBoucWen(const YAML::Node& node, std::string_view where) {
  RequireKnownKeys(node, where,
                   {"type", "initial_stiffness", "alpha", "yield_displacement", "A", "beta",
                    "gamma", "n", "max_substep"});
  const double k0 = ReadNumber(node, where, "initial_stiffness", "a positive stiffness in N/m");
  const double alpha = ReadNumber(node, where, "alpha", "a post-yield ratio in [0, 1]");
  const bool yield_form = static_cast<bool>(node["yield_displacement"]);
  const bool classic_form = node["A"] || node["beta"] || node["gamma"];
  if (yield_form == classic_form) {
    throw ConfigError(fmt::format(
        "{}: expected EITHER yield_displacement [m] OR the classic A, beta, gamma, n; {}",
        where, yield_form ? "both were given: remove one form" : "neither was given: add one"));
  }
  BoucWen::Parameters p;
  if (yield_form) {
    p = BoucWen::FromYieldDisplacement(
        k0, alpha, ReadNumber(node, where, "yield_displacement", "a positive length in m"),
        ReadNumber(node, where, "n", "an exponent n >= 1", 1.0));
  } else {
    p.initial_stiffness = k0;
    p.alpha = alpha;
    p.a = ReadNumber(node, where, "A", "a positive number (1 is usual)");
    p.beta = ReadNumber(node, where, "beta", "a number in 1/m^n");
    p.gamma = ReadNumber(node, where, "gamma", "a number in 1/m^n");
    p.n = ReadNumber(node, where, "n", "an exponent n >= 1");
  }
  p.max_substep = ReadNumber(node, where, "max_substep", "a non-negative length in m", 0.0);
  return std::make_unique<BoucWen>(p);
}

}  // namespace

std::unique_ptr<RestoringForceLaw> ParseRestoringForceLaw(const YAML::Node& node,
                                                          std::string_view where) {
  RequireMapping(node, where);
  if (!node["type"]) {
    throw ConfigError(fmt::format(
        "{}.type: missing; expected one of linear, cantilever, bouc_wen", where));
  }
  const std::string type = ReadString(node, where, "type", "");
  try {
    if (type == "linear") {
      RequireKnownKeys(node, where, {"type", "stiffness"});
      return std::make_unique<LinearSpring>(
          ReadNumber(node, where, "stiffness", "a finite stiffness in N/m"));
    }
    if (type == "cantilever") {
      RequireKnownKeys(node, where, {"type", "length", "width", "thickness", "youngs_modulus"});
      return MakeCantileverSpring(
          ReadNumber(node, where, "length", "a positive length in m (0.5 for the paper's beam)"),
          ReadNumber(node, where, "width", "a positive width in m (0.1 for the paper's beam)"),
          ReadNumber(node, where, "thickness",
                     "a positive thickness in m (0.005 for the paper's beam)"),
          ReadNumber(node, where, "youngs_modulus", "a positive modulus in Pa (210e9 for steel)"));
    }
    if (type == "bouc_wen") return ParseBoucWen(node, where);
  } catch (const ConfigError& e) {
    const std::string message = e.what();
    if (message.rfind(std::string(where), 0) == 0) throw;
    throw ConfigError(fmt::format("{}: {}", where, message));
  }
  ThrowField(node["type"], where, "type", type, "one of linear, cantilever, bouc_wen");
}

}  // namespace hybridtest::constitutive
