// See multi_emulated_bench.h.
#include "hybridtest/transfer/multi_emulated_bench.h"

#include <fmt/format.h>

#include <cmath>

#include "hybridtest/common/error.h"
#include "hybridtest/common/yaml_input.h"
#include "hybridtest/constitutive/parse_vector_law.h"
#include "hybridtest/transfer/safety_gate_group.h"
#include "hybridtest/transfer/actuator.h"
#include "hybridtest/transfer/lab_clock.h"
#include "hybridtest/transfer/load_cell.h"

namespace hybridtest::transfer {
namespace {

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

}  // namespace

bool IsMultiBench(const YAML::Node& bench) { return bench.IsMap() && bench["actuators"]; }

MultiBenchConfig ParseMultiBenchConfig(const YAML::Node& bench, std::string_view where_view) {
  const std::string where(where_view);
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
  MultiBenchConfig config;
  config.specimen = constitutive::ParseVectorLaw(bench["specimen"], static_cast<int>(n),
                                                 where + ".specimen");
  config.stiffness = config.specimen->initial_stiffness();
  for (std::size_t k = 0; k < n; ++k) {
    YAML::Node one(YAML::NodeType::Map);
    for (const auto& kv : bench) {
      const std::string key = kv.first.as<std::string>();
      if (key == "actuators" || key == "specimen" || key == "openfresco") continue;
      one[key] = Pick(kv.second, k, n, where + "." + key);
    }
    // Each actuator's own fallback (before the coupled prediction has every measurement).
    const double kkk = config.stiffness(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(k));
    one["specimen"]["type"] = "linear";
    one["specimen"]["stiffness"] = kkk;
    const unsigned long seed = bench["seed"] ? one["seed"].as<unsigned long>() : 1UL;
    one["seed"] = seed + k;
    config.actuators.push_back(
        ParseEmulatedBenchConfig(one, fmt::format("{} (actuator {})", where, k + 1)));
  }
  return config;
}

bool IsMultiBenchFile(const std::string& path) {
  try {
    // Read as every input file is (regular files only, bounded): a FIFO must not block here.
    return IsMultiBench(YamlInput::FromFile(path, "a 'bench:' mapping").root()["bench"]);
  } catch (const std::exception&) {
    return false;  // the one-actuator loader reports what is wrong with the file
  }
}

MultiBenchConfig LoadMultiBenchConfig(const std::string& path) {
  const YamlInput file = YamlInput::FromFile(path, "a 'bench:' mapping");
  file.CheckKeys(file.root(), "", {"bench", "openfresco"});  // as a bench of one actuator
  if (!IsMultiBench(file.root()["bench"])) {
    throw ConfigError(fmt::format("{}: expected a top-level 'bench:' mapping with `actuators:`",
                                  path));
  }
  return ParseMultiBenchConfig(file.root()["bench"], fmt::format("{}: bench", path));
}

MultiEmulatedBench::MultiEmulatedBench(const MultiBenchConfig& config) : config_(config) {
  const auto n = config_.actuators.size();
  if (n == 0 || config_.stiffness.rows() != static_cast<Eigen::Index>(n) ||
      config_.stiffness.cols() != static_cast<Eigen::Index>(n) || !config_.stiffness.allFinite()) {
    throw ConfigError(fmt::format("multi-actuator bench: {} actuators and a {} × {} stiffness: "
                                  "expected a finite n × n matrix", n, config_.stiffness.rows(),
                                  config_.stiffness.cols()));
  }
  const auto& first = config_.actuators[0];
  for (std::size_t k = 0; k < n; ++k) {
    const auto& a = config_.actuators[k];
    ValidateEmulatedBenchConfig(a);
    if (a.internal_step != first.internal_step ||
        a.units.metres_per_length_unit != first.units.metres_per_length_unit ||
        a.units.newtons_per_force_unit != first.units.newtons_per_force_unit) {
      throw ConfigError(fmt::format("multi-actuator bench: actuator {} has another internal step "
                                    "or other wire units than actuator 1; give them once for all",
                                    k + 1));
    }
    safety_.emplace_back(a.safety);
    actuators_.push_back(std::make_unique<Actuator>(a));
    load_cells_.push_back(std::make_unique<LoadCell>(a.noise_std, a.resolution, a.offset, a.seed));
  }
  clock_ = std::make_unique<LabClock>(first.realtime);
  specimen_ = config_.specimen ? config_.specimen->Clone()
                               : std::make_unique<constitutive::LinearCoupledLaw>(config_.stiffness);
  if (specimen_->num_axes() != static_cast<int>(n)) {
    throw ConfigError(fmt::format("multi-actuator bench: a specimen of {} axes on {} actuators",
                                  specimen_->num_axes(), n));
  }
  // The specimen starts deformed if an actuator does not start at its p0.
  Deform();
}

MultiEmulatedBench::~MultiEmulatedBench() = default;

void MultiEmulatedBench::Activate() {
  if (state_ == State::kConfigured) {
    for (std::size_t k = 0; k < safety_.size(); ++k) {
      safety_[k].SetStartPosition(config_.actuators[k].initial_position);
      const double kkk = config_.stiffness(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(k));
      if (kkk > 0.0) safety_[k].SetInitialStiffness(kkk);
    }
    clock_->Start();
  }
  state_ = State::kActive;
}

Measurement MultiEmulatedBench::Execute(double command) {
  if (num_actuators() != 1) {
    throw TransferError(fmt::format("multi-actuator bench: one command for {} actuators; a "
                                    "substructure with `setup: transform` sends one per actuator",
                                    num_actuators()));
  }
  Measurement m;
  Execute(std::span<const double>(&command, 1), std::span<Measurement>(&m, 1));
  return m;
}

Eigen::VectorXd MultiEmulatedBench::Deform() {
  const int n = num_actuators();
  std::vector<double> deformation(static_cast<std::size_t>(n));
  for (std::size_t k = 0; k < deformation.size(); ++k) {
    deformation[k] = actuators_[k]->position() - config_.actuators[k].p0;
  }
  Eigen::VectorXd force(n);
  specimen_->Trial(deformation, std::span<double>(force.data(), deformation.size()));
  specimen_->Commit();
  return force;
}

void MultiEmulatedBench::Execute(std::span<const double> commands, std::span<Measurement> out) {
  const auto n = static_cast<std::size_t>(num_actuators());
  if (commands.size() != n || out.size() != n) {
    throw TransferError(fmt::format("multi-actuator bench: {} commands for {} actuators",
                                    commands.size(), n));
  }
  if (state_ != State::kActive) {
    throw TransferError(fmt::format("multi-actuator bench: Execute while the bench is {}: call "
                                    "Activate() first (also to resume after a hold)",
                                    state_ == State::kHolding ? "holding" : "not active"));
  }
  const long index = command_count_++;
  const auto& first = config_.actuators[0];
  std::vector<double> target(n);
  for (std::size_t k = 0; k < n; ++k) target[k] = commands[k] * first.units.metres_per_length_unit;
  // 0. Every command is checked before any actuator moves.
  try {
    CheckCommands(safety_, &config_.stiffness, target, index, 0);
  } catch (...) {
    Hold();
    throw;
  }
  clock_->Advance(first.overhead);
  const double dt = first.internal_step;
  auto advance = [&]() {
    for (std::size_t k = 0; k < n; ++k) actuators_[k]->Step(target[k]);
    const Eigen::VectorXd force = Deform();
    for (std::size_t k = 0; k < n; ++k) {
      const double capacity = config_.actuators[k].capacity;
      if (!(std::abs(force(static_cast<Eigen::Index>(k))) <= capacity)) {
        Hold();
        throw SafetyStop("actuator_capacity", std::abs(force(static_cast<Eigen::Index>(k))),
                         capacity, index, 0, safety_[k].history(),
                         fmt::format("The drive of actuator {} tripped at position {:.6g} m: the "
                                     "specimen force exceeds its capacity; every actuator holds.",
                                     k + 1, actuators_[k]->position()));
      }
    }
    return force;
  };
  // 1–2. Move together until every actuator has settled for its dwell time.
  std::vector<double> dwell(n, 0.0);
  double phase_time = 0.0;
  for (;;) {
    advance();
    phase_time += dt;
    bool all = true;
    for (std::size_t k = 0; k < n; ++k) {
      const auto& a = config_.actuators[k];
      const bool inside = actuators_[k]->reference_arrived(target[k]) &&
                          std::abs(target[k] - actuators_[k]->position()) < a.settle_tolerance;
      dwell[k] = inside ? dwell[k] + dt : 0.0;
      all = all && inside && dwell[k] >= a.settle_dwell - 0.5 * dt;
    }
    if (all) break;
    if (phase_time > first.safety.timeout) {
      clock_->Advance(phase_time);
      Hold();
      throw TransferError(fmt::format("multi-actuator bench: the actuators did not all settle in "
                                      "{} s; check the lag parameters and settling", phase_time));
    }
  }
  // 3. Sample every load cell over the window (deviations from the first sample).
  const long samples = std::max(1L, std::lround(first.sampling_window / dt));
  std::vector<double> p_first(n), f_first(n), sum_dp(n, 0.0), sum_df(n, 0.0);
  for (long i = 0; i < samples; ++i) {
    const Eigen::VectorXd force = advance();
    for (std::size_t k = 0; k < n; ++k) {
      const double reading = load_cells_[k]->Sample(force(static_cast<Eigen::Index>(k)));
      if (i == 0) {
        p_first[k] = actuators_[k]->position();
        f_first[k] = reading;
      }
      sum_dp[k] += actuators_[k]->position() - p_first[k];
      sum_df[k] += reading - f_first[k];
    }
  }
  const double count = static_cast<double>(samples);
  clock_->Advance(phase_time + count * dt);
  for (std::size_t k = 0; k < n; ++k) {
    const double position = p_first[k] + sum_dp[k] / count;
    const double force = f_first[k] + sum_df[k] / count;
    try {
      safety_[k].CheckMeasurement(target[k], position, force, index, 0);
    } catch (...) {
      Hold();
      throw;
    }
    out[k] = {commands[k] + (position - target[k]) / first.units.metres_per_length_unit,
              force / first.units.newtons_per_force_unit, clock_->lab_time(), 0};
  }
  clock_->Pace();
}

void MultiEmulatedBench::Hold() noexcept {
  if (state_ == State::kActive) state_ = State::kHolding;
}

void MultiEmulatedBench::Deactivate() {
  Hold();
  state_ = State::kDeactivated;
}

std::string MultiEmulatedBench::Describe() const {
  std::string p0;
  for (const auto& a : config_.actuators) p0 += fmt::format("{}{:g}", p0.empty() ? "" : ", ", a.p0 * 1e3);
  return fmt::format("emulated bench with {} actuators ({}; p0 = [{}] mm; {}/{}; {})",
                     num_actuators(), specimen_->Describe(), p0,
                     config_.actuators[0].units.length_name,
                     config_.actuators[0].units.force_name,
                     config_.actuators[0].realtime ? "realtime" : "accelerated");
}

double MultiEmulatedBench::lab_time() const { return clock_->lab_time(); }
std::optional<std::vector<Measurement>> MultiEmulatedBench::ReadAll() const {
  const int n = num_actuators();
  std::vector<double> deformation(static_cast<std::size_t>(n));
  for (std::size_t k = 0; k < deformation.size(); ++k) {
    deformation[k] = actuators_[k]->position() - config_.actuators[k].p0;
  }
  // The specimen's forces at the committed state: a trial of a copy of its law.
  auto law = specimen_->Clone();
  std::vector<double> force(deformation.size());
  law->Trial(deformation, force);
  std::vector<Measurement> out;
  for (std::size_t k = 0; k < deformation.size(); ++k) {
    const EmulatedBenchConfig& a = config_.actuators[k];
    out.push_back(Measurement{actuators_[k]->position() / a.units.metres_per_length_unit,
                              (force[k] + a.offset) / a.units.newtons_per_force_unit,
                              clock_->lab_time(), 0});
  }
  return out;
}

double MultiEmulatedBench::actuator_position(int k) const {
  return actuators_[static_cast<std::size_t>(k)]->position();
}

nlohmann::json MultiEmulatedBench::SaveState() const {
  nlohmann::json actuators = nlohmann::json::array(), cells = nlohmann::json::array(),
                 safety = nlohmann::json::array();
  for (std::size_t k = 0; k < actuators_.size(); ++k) {
    actuators.push_back(actuators_[k]->SaveState());
    cells.push_back(load_cells_[k]->SaveState());
    safety.push_back(safety_[k].SaveState());
  }
  return {{"kind", "multi_emulated"}, {"command_count", command_count_},
          {"lab_time_s", clock_->lab_time()}, {"actuators", actuators}, {"load_cells", cells},
          {"safety", safety}, {"specimen", specimen_->SaveState()}};
}

void MultiEmulatedBench::RestoreState(const nlohmann::json& state) {
  try {
    const std::size_t n = actuators_.size();
    if (state.value("kind", "") != "multi_emulated" || state.at("actuators").size() != n ||
        state.at("load_cells").size() != n || state.at("safety").size() != n) {
      throw Error(fmt::format("it is not the state of an emulated bench with {} actuators", n));
    }
    for (std::size_t k = 0; k < n; ++k) {
      actuators_[k]->RestoreState(state.at("actuators")[k]);
      load_cells_[k]->RestoreState(state.at("load_cells")[k].get<std::string>());
      safety_[k].RestoreState(state.at("safety")[k]);
    }
    specimen_->RestoreState(state.at("specimen"));
    clock_->Restore(state.at("lab_time_s").get<double>());
    command_count_ = state.at("command_count").get<long>();
  } catch (const nlohmann::json::exception& e) {
    throw Error(fmt::format("multi-actuator emulated bench: cannot restore its state: {}",
                            e.what()));
  }
}

}  // namespace hybridtest::transfer
