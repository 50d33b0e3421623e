// Model files: extra first-order states (`states:`), such as a controller's integrator or a
// filter. See model_file.h and docs/model-files.md.
//
//   states:
//     z_int: {rate: "omega_ref - u_rotor", initial: 0, unit: rad, description: PI integrator}
//
// Each state z joins the state vector after q and u (x = [q; u; z]) with ż = rate(t, q, u, z):
// the rate may read t, coordinates, speeds, states, time functions, tables and velocity() /
// angular_velocity(), but not a slot (the hybrid schemes' coupling assumes ż free of r). Loads
// read a state by its name.
#include <fmt/core.h>

#include <cmath>

#include "hybridtest/common/error.h"
#include "hybridtest/modelfile/compiled_scalar.h"
#include "hybridtest/modelfile/file_context.h"
#include "hybridtest/modelfile/units.h"

namespace hybridtest::modelfile::internal {

void ReadExtraStates(FileContext& c, const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) return;
  c.in.RequireMapping(node, "states");
  for (const auto& kv : node) {
    const std::string name = kv.first.as<std::string>();
    const std::string kp = "states." + name;
    if (!kv.second.IsMap()) {
      c.in.ThrowValue(kv.second, kp, "a mapping {rate: <formula>, initial: <value>, unit: <SI "
                                     "unit>, description: <text>}");
    }
    c.in.CheckKeys(kv.second, kp, {"rate", "initial", "unit", "description"});
    // The unit: SI (the state is integrated as it is), any dimension.
    const std::string unit = c.in.ReadString(kv.second, kp, "unit", "1");
    std::string why;
    const std::optional<Unit> parsed = ParseUnit(unit, &why);
    if (!parsed) {
      throw ConfigError(fmt::format("{} = '{}': {}", c.Where(kv.second["unit"], kp + ".unit"),
                                    unit, why));
    }
    if (parsed->to_si != 1.0) {
      throw ConfigError(fmt::format(
          "{} = '{}': a state is integrated in SI, so write `unit: {}` ({:g} {} = 1 {}); its "
          "initial value may still be written `initial: 5 {}`",
          c.Where(kv.second["unit"], kp + ".unit"), unit, parsed->si, 1.0 / parsed->to_si, unit,
          parsed->si, unit));
    }
    const double initial =
        kv.second["initial"].IsDefined()
            ? c.Constant(kv.second["initial"], kp + ".initial",
                         fmt::format("the state's value at t = 0 in {}", unit),
                         Dim::FromUnit(parsed->dim))
            : 0.0;
    const YAML::Node rate_node =
        c.Require(kv.second, "rate", kp, fmt::format("its rate of change ż in {}/s, a formula", unit));
    Dim per_second = Dim::FromUnit(parsed->dim);
    per_second.e[2] -= 1;
    Expression rate = c.Parse(rate_node, kp + ".rate");
    if (rate.Uses(Op::kSlot)) {
      throw ConfigError(fmt::format(
          "{} = '{}': reads a slot (a restoring force); a state's rate may use t, coordinates, "
          "speeds, states, time functions, tables and velocities, not r (the hybrid schemes "
          "need ż free of r); model the measured force as a load instead",
          c.Where(rate_node, kp + ".rate"), rate_node.Scalar()));
    }
    c.CheckDim(rate_node, kp + ".rate", rate, per_second);
    auto compiled = std::make_shared<const CompiledScalar>(std::move(rate));
    c.builder->AddExtraState(
        {name, unit, c.in.ReadString(kv.second, kp, "description", "")}, initial,
        [compiled](const auto& a) {
          using T = std::decay_t<decltype(a.t)>;
          const Variables<T> v{a.t, a.q, a.u, {}, a.time_values, a.z};
          return compiled->Eval(v);
        });
  }
}

}  // namespace hybridtest::modelfile::internal
