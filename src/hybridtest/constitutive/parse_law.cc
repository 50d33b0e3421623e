#include "hybridtest/constitutive/parse_law.h"

#include <fmt/format.h>

#include "hybridtest/common/error.h"
#include "hybridtest/common/yaml_input.h"
#include "hybridtest/constitutive/bouc_wen.h"
#include "hybridtest/constitutive/cantilever.h"
#include "hybridtest/constitutive/linear_spring.h"

namespace hybridtest::constitutive {
namespace {

std::unique_ptr<RestoringForceLaw> ParseBoucWen(const YamlInput& in, const YAML::Node& node,
                                                std::string_view where) {
  in.CheckKeys(node, where,
               {"type", "initial_stiffness", "alpha", "yield_displacement", "A", "beta", "gamma",
                "n", "max_substep"});
  const double k0 = in.ReadNumber(node, where, "initial_stiffness", "a positive stiffness in N/m");
  const double alpha = in.ReadNumber(node, where, "alpha", "a post-yield ratio in [0, 1]");
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
        k0, alpha, in.ReadNumber(node, where, "yield_displacement", "a positive length in m"),
        in.ReadNumber(node, where, "n", "an exponent n >= 1", 1.0));
  } else {
    p.initial_stiffness = k0;
    p.alpha = alpha;
    p.a = in.ReadNumber(node, where, "A", "a positive number (1 is usual)");
    p.beta = in.ReadNumber(node, where, "beta", "a number in 1/m^n");
    p.gamma = in.ReadNumber(node, where, "gamma", "a number in 1/m^n");
    p.n = in.ReadNumber(node, where, "n", "an exponent n >= 1");
  }
  p.max_substep = in.ReadNumber(node, where, "max_substep", "a non-negative length in m", 0.0);
  return std::make_unique<BoucWen>(p);
}

}  // namespace

std::unique_ptr<RestoringForceLaw> ParseRestoringForceLaw(const YAML::Node& node,
                                                          std::string_view where) {
  const YamlInput in = YamlInput::ForNode(node);
  in.RequireMapping(node, where);
  const std::string type =
      in.String(node["type"], JoinKeyPath(where, "type"), "one of linear, cantilever, bouc_wen");
  try {
    if (type == "linear") {
      in.CheckKeys(node, where, {"type", "stiffness"});
      return std::make_unique<LinearSpring>(
          in.ReadNumber(node, where, "stiffness", "a finite stiffness in N/m"));
    }
    if (type == "cantilever") {
      in.CheckKeys(node, where, {"type", "length", "width", "thickness", "youngs_modulus"});
      return MakeCantileverSpring(
          in.ReadNumber(node, where, "length", "a positive length in m (0.5 for the paper's beam)"),
          in.ReadNumber(node, where, "width", "a positive width in m (0.1 for the paper's beam)"),
          in.ReadNumber(node, where, "thickness",
                        "a positive thickness in m (0.005 for the paper's beam)"),
          in.ReadNumber(node, where, "youngs_modulus",
                        "a positive modulus in Pa (210e9 for steel)"));
    }
    if (type == "bouc_wen") return ParseBoucWen(in, node, where);
  } catch (const ConfigError& e) {
    const std::string message = e.what();
    if (message.rfind(std::string(where), 0) == 0) throw;
    throw ConfigError(fmt::format("{}: {}", where, message));
  }
  in.ThrowValue(node["type"], JoinKeyPath(where, "type"), "one of linear, cantilever, bouc_wen");
}

}  // namespace hybridtest::constitutive
