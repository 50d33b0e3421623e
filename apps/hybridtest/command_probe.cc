// hybridtest probe CONFIG [--bench HOST:PORT]: before a test, look at every physical slot's
// bench without moving it. First the checks of runner::CheckPhysicalSlotsBeforeMoving (p0 and limits
// against what the bench announces); then, where the transfer system can read without a
// command (TransferSystem::Probe: the emulated bench, a Modbus controller; not a remote bench
// server), one reading of position, force and status, checked in SI against the slot's setup
// and limits:
//   - the bench reports no problem (fault, a value that is not a number);
//   - the position lies inside the stroke [safety.stroke_min, stroke_max];
//   - |position − setup.p0| ≤ safety.max_increment: the first command starts from p0, so an
//     actuator elsewhere would jump (a hint names a factor of 1000 as a unit slip);
//   - |force| ≤ safety.force_soft: the specimen must be unloaded at rest.
// A specimen on several actuators: every actuator read (ReadAll) and checked the same way.
// Prints one block per slot and exits 0 when every check passes, 2 (ConfigError) otherwise.
// Nothing is written to the bench: no command, no coil, no drive enabled.
#include <fmt/core.h>

#include <cmath>
#include <memory>
#include <optional>

#include "command.h"
#include "hybridtest/common/error.h"
#include "hybridtest/io/config.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/runner/pre_move_checks.h"
#include "hybridtest/substructures/substructure.h"

namespace hybridtest::app {
namespace {

struct ProbeOptions {
  std::string config;
  std::optional<std::string> bench;
};

// What is wrong with one actuator's reading (SI): the bench's own problem (may be empty), then
// position and force against the stroke, p0 and force_soft. `who` prefixes each message
// ("" for a one-actuator slot, "actuator 2: " for one of several).
std::vector<std::string> ProbeProblems(const std::string& bench_problem,
                                       const transfer::SafetyLimits& l, double p0,
                                       double position, double force, const std::string& who) {
  std::vector<std::string> problems;
  if (!bench_problem.empty()) problems.push_back(bench_problem);
  if (!std::isfinite(position) || !std::isfinite(force)) {
    if (bench_problem.empty()) problems.push_back(who + "a position or force that is not a number");
    return problems;
  }
  if (position < l.stroke_min || position > l.stroke_max) {
    problems.push_back(fmt::format("{}position {} m is outside the stroke [{}, {}] m", who,
                                   position, l.stroke_min, l.stroke_max));
  }
  if (std::abs(position - p0) > l.max_increment) {
    const double ratio = p0 != 0.0 ? std::abs(position / p0) : 0.0;
    problems.push_back(fmt::format(
        "{}position {} m is {} m from setup.p0 = {} m, more than safety.max_increment = {} m: "
        "the first command would jump{}; move the actuator to p0, or correct setup.p0", who,
        position, std::abs(position - p0), p0, l.max_increment,
        (ratio > 300 && ratio < 3000) || (ratio > 1.0 / 3000 && ratio < 1.0 / 300)
            ? " (a factor of about 1000: a unit slip between mm and m?)"
            : ""));
  }
  if (std::abs(force) > l.force_soft) {
    problems.push_back(fmt::format(
        "{}force {} N at rest exceeds safety.force_soft = {} N: the specimen is loaded before "
        "the test; check p0, the load-cell zero (setup.load_cell_zero) and the force unit", who,
        force, l.force_soft));
  }
  return problems;
}

// A specimen on several actuators: Probe() for the controller's status (it connects if it
// must), then every actuator read without moving (ReadAll) and checked like one slot.
// Returns whether it was probed; adds 1 to failed if a check does not pass.
bool ProbeActuators(const std::string& name, substructures::Substructure& sub,
                    transfer::TransferSystem& bench, long& failed) {
  fmt::print("{}: {}\n", name, bench.Describe());
  const std::optional<transfer::ProbeReading> reading = bench.Probe();
  const auto all = bench.ReadAll();
  if (!all || static_cast<int>(all->size()) != sub.num_actuators()) {
    if (reading && !reading->problem.empty()) {
      fmt::print("  PROBLEM: {}\n", reading->problem);
      ++failed;
      return true;
    }
    fmt::print("  not probed: this transfer system cannot read its actuators without moving; "
               "their checks run when the test connects\n");
    return false;
  }
  if (reading && !reading->status.empty()) fmt::print("  status   {}\n", reading->status);
  const transfer::BenchUnits units = bench.bench_units();
  std::vector<std::string> problems;
  if (reading && !reading->problem.empty()) problems.push_back(reading->problem);
  for (int k = 0; k < sub.num_actuators(); ++k) {
    const transfer::Measurement& m = (*all)[static_cast<std::size_t>(k)];
    const auto [position, force] = sub.ActuatorSi(k, m, units);
    const double p0 = sub.actuator_p0(k).value_or(0.0);
    fmt::print("  actuator {}: position {} {} = {} m (setup.p0 = {} m), force {} {} = {} N\n",
               k + 1, m.position, units.length_name, position, p0, m.force, units.force_name,
               force);
    for (std::string& p : ProbeProblems("", *sub.actuator_limits(k), p0, position,
                                        force, fmt::format("actuator {}: ", k + 1))) {
      problems.push_back(std::move(p));
    }
  }
  for (const std::string& p : problems) fmt::print("  PROBLEM: {}\n", p);
  if (problems.empty()) fmt::print("  ok: every actuator at p0, unloaded, inside its limits\n");
  failed += problems.empty() ? 0 : 1;
  return true;
}

void RunProbe(const ProbeOptions& options) {
  const io::SimulationConfig cfg = io::LoadSimulationConfig(options.config);
  const io::RunSpec spec = io::CompileRunSpec(cfg, {options.bench, true, "", std::nullopt});
  std::vector<std::unique_ptr<substructures::Substructure>> subs;
  for (const auto& sub : spec.substructures) subs.push_back(sub.Build());
  runner::CheckPhysicalSlotsBeforeMoving(spec, subs);
  long failed = 0, probed = 0, physical = 0;
  for (std::size_t s = 0; s < subs.size(); ++s) {
    // The slot map's blocks: one actuator and one slot, or several (every actuator read).
    substructures::Substructure& sub = *subs[s];
    transfer::TransferSystem* bench = sub.transfer_system();
    if (bench == nullptr) continue;
    ++physical;
    const std::string name = spec.substructures[s].slot;
    if (sub.num_actuators() > 1 || sub.num_slots() > 1) {
      probed += ProbeActuators(name, sub, *bench, failed) ? 1 : 0;
      continue;
    }
    fmt::print("{}: {}\n", name, bench->Describe());
    const std::optional<transfer::ProbeReading> reading = bench->Probe();
    if (!reading) {
      fmt::print("  not probed: this transfer system cannot read without moving; its checks "
                 "run when the test connects\n");
      continue;
    }
    ++probed;
    const transfer::BenchUnits units = bench->bench_units();
    const auto [position, force] = sub.ActuatorSi(0, reading->measurement, units);
    const double p0 = sub.actuator_p0(0).value_or(0.0);
    fmt::print("  position {} {} = {} m (setup.p0 = {} m)\n", reading->measurement.position,
               units.length_name, position, p0);
    fmt::print("  force    {} {} = {} N (load-cell zero removed)\n", reading->measurement.force,
               units.force_name, force);
    if (!reading->status.empty()) fmt::print("  status   {}\n", reading->status);
    const std::vector<std::string> problems = ProbeProblems(
        reading->problem, *sub.actuator_limits(0), p0, position, force, "");
    for (const std::string& p : problems) fmt::print("  PROBLEM: {}\n", p);
    if (problems.empty()) fmt::print("  ok: at p0, unloaded, inside the limits\n");
    failed += problems.empty() ? 0 : 1;
  }
  if (physical == 0) {
    fmt::print("{}: no physical slot; nothing to probe\n", options.config);
    return;
  }
  if (failed > 0) {
    throw ConfigError(fmt::format("{}: {} of {} probed slots are not ready (see above); nothing "
                                  "was moved", options.config, failed, probed));
  }
  fmt::print("probe: {} of {} physical slots read and ready; nothing was moved\n", probed,
             physical);
}

void AddProbeCommand(CLI::App& root) {
  auto options = std::make_shared<ProbeOptions>();
  CLI::App* command = root.add_subcommand(
      "probe", "Before a test: read each physical slot's position, force and status without "
               "moving, and check them against p0 and the limits");
  command->add_option("config", options->config, "run configuration (YAML)")->required();
  command->add_option("--bench", options->bench,
                      "HOST:PORT of a bench server (remote) or a Modbus/TCP controller (modbus)");
  command->callback([options] { RunProbe(*options); });
}

const CommandRegistration kRegistration{"probe", &AddProbeCommand};

}  // namespace
}  // namespace hybridtest::app
