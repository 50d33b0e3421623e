// See bench_spec.h.
#include "hybridtest/transfer/bench_spec.h"

#include <fmt/format.h>

#include <cmath>

#include "hybridtest/common/error.h"
#include "hybridtest/common/yaml_input.h"
#include "hybridtest/constitutive/parse_vector_law.h"

namespace hybridtest::transfer {
namespace {

// A scalar restoring-force law as a law of one axis: the specimen of a one-actuator bench file,
// evaluated exactly as the scalar law (same calls, same results, same saved state).
class OneAxisLaw final : public constitutive::VectorRestoringForceLaw {
 public:
  explicit OneAxisLaw(std::unique_ptr<constitutive::RestoringForceLaw> law)
      : law_(std::move(law)) {}
  int num_axes() const override { return 1; }
  void Trial(std::span<const double> u, std::span<double> force) override {
    force[0] = law_->Trial(u[0]);
  }
  void Commit() override { law_->Commit(); }
  Eigen::MatrixXd initial_stiffness() const override {
    return Eigen::MatrixXd::Constant(1, 1, law_->initial_stiffness());
  }
  std::unique_ptr<VectorRestoringForceLaw> Clone() const override {
    return std::make_unique<OneAxisLaw>(law_->Clone());
  }
  std::string Describe() const override { return law_->Describe(); }
  nlohmann::json SaveState() const override { return law_->SaveState(); }
  void RestoreState(const nlohmann::json& state) override { law_->RestoreState(state); }

 private:
  std::unique_ptr<constitutive::RestoringForceLaw> law_;
};

// Actuator k's view of a node: every sequence (a per-actuator list) replaced by its k-th value.
YAML::Node Pick(const YAML::Node& node, std::size_t k, std::size_t n, const std::string& where) {
  if (node.IsSequence()) {
    if (node.size() != n) {
      throw ConfigError(fmt::format("{}: a list of {} values; expected one value per actuator "
                                    "({}), or one scalar for all", where, node.size(), n));
    }
    return YAML::Clone(node[k]);
  }
  if (!node.IsMap()) return YAML::Clone(node);
  YAML::Node out(YAML::NodeType::Map);
  for (const auto& kv : node) {
    const std::string key = kv.first.as<std::string>();
    out[key] = Pick(kv.second, k, n, where + "." + key);
  }
  return out;
}

// The `actuators: n` form.
EmulatedBenchSpec ParseSeveral(const YAML::Node& bench, const std::string& where) {
  const YamlInput in = YamlInput::ForNode(bench);
  const double count = in.Number(bench["actuators"], where + ".actuators",
                                 "the number of actuators (an integer ≥ 1)");
  if (!(count >= 1.0) || count != std::floor(count) || count > 64.0) {
    throw ConfigError(fmt::format("{}.actuators = {}: expected an integer from 1 to 64", where, count));
  }
  const auto n = static_cast<std::size_t>(count);
  if (bench["faults"]) {
    throw ConfigError(fmt::format("{}.faults: not available on a bench with `actuators:`; remove "
                                  "it (inject faults on a one-actuator bench)", where));
  }
  EmulatedBenchSpec spec;
  spec.specimen = constitutive::ParseVectorLaw(bench["specimen"], static_cast<int>(n),
                                               where + ".specimen");
  spec.stiffness = spec.specimen->initial_stiffness();
  for (std::size_t k = 0; k < n; ++k) {
    YAML::Node one(YAML::NodeType::Map);
    for (const auto& kv : bench) {
      const std::string key = kv.first.as<std::string>();
      if (key == "actuators" || key == "specimen" || key == "openfresco") continue;
      one[key] = Pick(kv.second, k, n, where + "." + key);
    }
    // Each actuator's own fallback (before the coupled prediction has every measurement).
    const auto i = static_cast<Eigen::Index>(k);
    one["specimen"]["type"] = "linear";
    one["specimen"]["stiffness"] = spec.stiffness(i, i);
    unsigned long seed = 1UL;
    if (bench["seed"]) {
      const double given = in.Number(one["seed"], where + ".seed",
                                     "the load cells' random seed (an integer ≥ 0)");
      if (!(given >= 0.0) || given != std::floor(given) || given > 4294967295.0) {
        throw ConfigError(fmt::format("{}.seed = {}: expected an integer from 0 to 4294967295 "
                                      "(actuator k's load cell uses seed + k − 1)", where, given));
      }
      seed = static_cast<unsigned long>(given);
    }
    one["seed"] = seed + k;
    spec.actuators.push_back(
        ParseEmulatedBenchConfig(one, fmt::format("{} (actuator {})", where, k + 1)));
  }
  return spec;
}

}  // namespace

EmulatedBenchSpec OneActuatorSpec(const EmulatedBenchConfig& config) {
  if (!config.specimen) {
    throw ConfigError("emulated bench: specimen: missing; expected a restoring-force law");
  }
  EmulatedBenchSpec spec;
  spec.actuators = {config};
  spec.specimen = std::make_shared<OneAxisLaw>(config.specimen->Clone());
  spec.stiffness = Eigen::MatrixXd::Constant(1, 1, config.specimen->initial_stiffness());
  spec.coupled_safety = false;
  return spec;
}

EmulatedBenchSpec ParseEmulatedBenchSpec(const YAML::Node& bench, std::string_view where) {
  // IsDefined first: a missing `bench:` is an invalid node, on which IsMap() throws (the
  // one-actuator parser then names the missing mapping).
  if (bench.IsDefined() && bench.IsMap() && bench["actuators"]) {
    try {
      return ParseSeveral(bench, std::string(where));
    } catch (const YAML::Exception& e) {
      // A value of a shape no check above expected (a key that is not a name, ...).
      throw ConfigError(fmt::format(
          "{}: {}: give that value as a bench file of several actuators takes it (see "
          "examples/06_blade_two_actuators/bench-2act.yaml)", where, e.what()));
    }
  }
  return OneActuatorSpec(ParseEmulatedBenchConfig(bench, where));
}

EmulatedBenchSpec LoadEmulatedBenchSpec(const std::string& path) {
  const YamlInput file = YamlInput::FromFile(path, "a 'bench:' mapping");
  // A misspelt or misplaced section (`safety:` at the top level instead of under `bench:`)
  // would be ignored: the keys a bench file may hold are these.
  file.CheckKeys(file.root(), "", {"bench", "openfresco"});
  if (!file.root()["bench"]) {
    throw ConfigError(fmt::format(
        "{}: expected a top-level 'bench:' mapping (see examples/rotor/bench-ideal.yaml)", path));
  }
  return ParseEmulatedBenchSpec(file.root()["bench"], fmt::format("{}: bench", path));
}

}  // namespace hybridtest::transfer
