// See parse_vector_law.h.
#include "hybridtest/constitutive/parse_vector_law.h"

#include <fmt/format.h>

#include "hybridtest/common/error.h"
#include "hybridtest/common/yaml_input.h"
#include "hybridtest/constitutive/bouc_wen_biaxial.h"

namespace hybridtest::constitutive {
namespace {

constexpr const char* kTypes = "one of linear, bouc_wen_biaxial";

// One positive value per axis: a list of `axes` values, or one scalar for all.
std::vector<double> PerAxis(const YamlInput& in, const YAML::Node& node, const std::string& path,
                            int axes, const char* expected) {
  const auto n = static_cast<std::size_t>(axes);
  if (!node) {
    throw ConfigError(fmt::format("{}: missing; expected {}, a list of {} (one per actuator) or "
                                  "one value for all", path, expected, n));
  }
  if (node.IsSequence()) {
    if (node.size() != n) {
      throw ConfigError(fmt::format("{}: a list of {} values; expected {} (one per actuator) or "
                                    "one value for all", path, node.size(), n));
    }
    return in.Numbers(node, path, expected);
  }
  return std::vector<double>(n, in.Number(node, path, expected));
}

std::unique_ptr<VectorRestoringForceLaw> ParseLinear(const YamlInput& in, const YAML::Node& node,
                                                     int axes, const std::string& where) {
  in.CheckKeys(node, where, {"type", "stiffness"});
  const auto n = static_cast<std::size_t>(axes);
  const YAML::Node k = node["stiffness"];
  const char* expected = "[[k11, k12, ...], ...] in N/m, one row per actuator";
  if (!k || !k.IsSequence() || k.size() != n) {
    throw ConfigError(fmt::format("{}.stiffness: expected {} ({} × {})", where, expected, n, n));
  }
  Eigen::MatrixXd m(axes, axes);
  for (std::size_t i = 0; i < n; ++i) {
    if (!k[i].IsSequence() || k[i].size() != n) {
      throw ConfigError(fmt::format("{}.stiffness row {}: expected {} values ({})", where, i + 1,
                                    n, expected));
    }
    for (std::size_t j = 0; j < n; ++j) {
      m(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = in.Number(
          k[i][j], fmt::format("{}.stiffness[{}][{}]", where, i, j), "a stiffness in N/m");
    }
  }
  return std::make_unique<LinearCoupledLaw>(std::move(m));
}

std::unique_ptr<VectorRestoringForceLaw> ParseBoucWenBiaxial(const YamlInput& in,
                                                             const YAML::Node& node, int axes,
                                                             const std::string& where) {
  in.CheckKeys(node, where, {"type", "initial_stiffness", "yield_displacement", "alpha", "A",
                             "beta", "gamma", "max_substep"});
  BoucWenBiaxial::Parameters p;
  p.initial_stiffness = PerAxis(in, node["initial_stiffness"], where + ".initial_stiffness",
                                axes, "a positive stiffness in N/m");
  p.yield_displacement = PerAxis(in, node["yield_displacement"], where + ".yield_displacement",
                                 axes, "a positive yield displacement in m");
  p.alpha = in.ReadNumber(node, where, "alpha", "a post-yield stiffness ratio in [0, 1]");
  p.a = in.ReadNumber(node, where, "A", "a positive number (1 is usual)", 1.0);
  p.beta = in.ReadNumber(node, where, "beta", "a dimensionless number (0.5 is usual)", 0.5);
  p.gamma = in.ReadNumber(node, where, "gamma", "a dimensionless number (0.5 is usual)", 0.5);
  p.max_substep = in.ReadNumber(node, where, "max_substep",
                                "a positive sub-step in u / Y (1/200 is the default)", 1.0 / 200.0);
  return std::make_unique<BoucWenBiaxial>(p);
}

}  // namespace

std::unique_ptr<VectorRestoringForceLaw> ParseVectorLaw(const YAML::Node& node, int axes,
                                                        std::string_view where_view) {
  const std::string where(where_view);
  const YamlInput in = YamlInput::ForNode(node);
  if (!node || !node.IsMap()) {
    throw ConfigError(fmt::format("{}: expected a mapping {{type: ...}} with type {}", where,
                                  kTypes));
  }
  const std::string type = in.String(node["type"], where + ".type", kTypes);
  try {
    if (type == "linear") return ParseLinear(in, node, axes, where);
    if (type == "bouc_wen_biaxial") return ParseBoucWenBiaxial(in, node, axes, where);
  } catch (const ConfigError& e) {
    const std::string message = e.what();
    if (message.find(where) != std::string::npos) throw;
    throw ConfigError(fmt::format("{}: {}", where, message));
  }
  throw ConfigError(fmt::format("{}.type = {}: expected {} (a bench with `actuators:` takes a "
                                "coupled specimen in actuator coordinates)", where, type, kTypes));
}

}  // namespace hybridtest::constitutive
