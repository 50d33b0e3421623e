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
// A specimen on several actuators: every actuator read and checked the same way.
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

// One block of the slot map (a substructure of one or several actuators): Probe() reads every
// actuator with the controller's status, without moving; each actuator is checked in SI.
// Returns whether it was probed; adds 1 to failed if a check does not pass.
bool ProbeActuators(const std::string& name, substructures::Substructure& sub,
                    transfer::TransferSystem& bench, long& failed) {
  fmt::print("{}: {}\n", name, bench.Describe());
  const std::optional<transfer::ProbeReading> reading = bench.Probe();
  const int n = sub.num_actuators();
  if (!reading || static_cast<int>(reading->measurements.size()) != n) {
    if (reading && !reading->problem.empty()) {
      fmt::print("  PROBLEM: {}\n", reading->problem);
      ++failed;
      return true;
    }
    fmt::print("  not probed: this transfer system cannot read {} without moving; {} checks "
               "run when the test connects\n", n == 1 ? "its actuator" : "its actuators",
               n == 1 ? "its" : "their");
    return false;
  }
  const transfer::BenchUnits units = bench.bench_units();
  std::vector<std::string> problems;
  for (int k = 0; k < n; ++k) {
    const transfer::Measurement& m = reading->measurements[static_cast<std::size_t>(k)];
    const auto [position, force] = sub.ActuatorSi(k, m, units);
    const double p0 = sub.actuator_p0(k).value_or(0.0);
    if (n == 1) {
      fmt::print("  position {} {} = {} m (setup.p0 = {} m)\n", m.position, units.length_name,
                 position, p0);
      fmt::print("  force    {} {} = {} N (load-cell zero removed)\n", m.force,
                 units.force_name, force);
    } else {
      fmt::print("  actuator {}: position {} {} = {} m (setup.p0 = {} m), force {} {} = {} N\n",
                 k + 1, m.position, units.length_name, position, p0, m.force, units.force_name,
                 force);
    }
    // The bench's own problem with the first actuator (it names the actuator it concerns).
    for (std::string& p : ProbeProblems(k == 0 ? reading->problem : "", *sub.actuator_limits(k),
                                        p0, position, force,
                                        n == 1 ? "" : fmt::format("actuator {}: ", k + 1))) {
      problems.push_back(std::move(p));
    }
  }
  if (!reading->status.empty()) fmt::print("  status   {}\n", reading->status);
  for (const std::string& p : problems) fmt::print("  PROBLEM: {}\n", p);
  if (problems.empty()) {
    fmt::print("  ok: {}\n", n == 1 ? "at p0, unloaded, inside the limits"
                                     : "every actuator at p0, unloaded, inside its limits");
  }
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
    probed += ProbeActuators(spec.substructures[s].slot, sub, *bench, failed) ? 1 : 0;
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

const CommandRegistration kCommandProbeRegistration{"probe", &AddProbeCommand};

}  // namespace
}  // namespace hybridtest::app
