// hybridtest plan CONFIG [--tolerance 0.01] [--seeds 3] [--emulate BENCH.yaml] [--keep DIR]
//                       [--quiet]
// A real-time config (a `real_time:` block) plans compensators and steps instead
// (runner/plan_real_time.h).
// The day before a test: candidate schemes against emulated specimens, their specimen
// evaluations, lab time and error against a fine numerical reference, and the cheapest one
// that meets the tolerance (runner/plan.h).
#include <fmt/core.h>

#include <cmath>
#include <cstdio>

#include <yaml-cpp/yaml.h>

#include "cli_values.h"
#include "command.h"
#include "hybridtest/common/error.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/runner/plan.h"
#include "hybridtest/runner/plan_real_time.h"

namespace hybridtest::app {
namespace {

struct PlanCommandOptions {
  std::string config;
  double tolerance = 0.01;
  std::string emulate;
  std::string keep;
  bool overwrite = false;  // with --keep: replace an earlier plan's files in that folder
  int seeds = 3;
  bool quiet = false;
};

std::string Duration(double seconds) {
  const long s = std::lround(seconds);
  return fmt::format("{}h{:02}m{:02}s", s / 3600, (s % 3600) / 60, s % 60);
}

std::string Row(const runner::PlanResult& r) {
  if (!r.ok) return fmt::format("{:<44} failed: {}", r.candidate.label, r.failure);
  return fmt::format("{:<48} {:>11} {:>11} {:>8.3f} % {:>9} {:>11}", r.candidate.label,
                     r.evaluations, Duration(r.lab_time), 100.0 * r.error, r.reversals,
                     r.force_reversals);
}

// The configured test with the candidate's scheme, as a complete config: the integrator
// section replaced, and `initial_stiffness: measure` on every physical slot an
// operator-splitting scheme needs K0 for and that gives none (plan measured it the same way).
std::string RecommendedConfig(const io::RunSpec& spec, const runner::PlanCandidate& c) {
  YAML::Node root = YAML::Load(spec.source.config_text);
  YAML::Node integrator;
  integrator["scheme"] = schemes::SchemeKindName(c.scheme.kind);
  if (c.scheme.kind == schemes::SchemeKind::kRungeKutta) integrator["tableau"] = c.tableau.name;
  integrator["dt"] = fmt::format("{}", c.dt);
  if (c.scheme.kind == schemes::SchemeKind::kAlphaOs) {
    integrator["alpha"] = fmt::format("{}", c.scheme.alpha);
  }
  if (c.scheme.kind == schemes::SchemeKind::kMrOs) {
    integrator["substep"] = fmt::format("{}", c.scheme.substep);
  }
  if (c.scheme.adaptive.enabled) {
    integrator["adaptive"]["tolerance"] = fmt::format("{:.3g}", c.scheme.adaptive.tolerance);
    integrator["adaptive"]["dt_min"] = fmt::format("{}", c.scheme.adaptive.dt_min);
    integrator["adaptive"]["dt_max"] = fmt::format("{}", c.scheme.adaptive.dt_max);
  }
  root["integrator"] = integrator;
  if (c.scheme.kind != schemes::SchemeKind::kRungeKutta) {
    for (const auto& sub : spec.substructures) {
      if (sub.physical && !sub.physical->initial_stiffness && !sub.physical->safety_stiffness &&
          !sub.physical->stiffness_ramp) {
        root["substructures"][sub.slot]["initial_stiffness"] = "measure";
      }
    }
  }
  YAML::Emitter out;
  out << root;
  return std::string(out.c_str()) + "\n";
}

// A real-time config: compensators and steps in virtual time (runner/plan_real_time.h).
void ExecuteRealTimePlan(const PlanCommandOptions& opt) {
  auto num = [](double v, const char* unit) {
    return std::isfinite(v) ? fmt::format("{:.3g}{}", v, unit) : std::string("—");
  };
  auto first_sentence = [](const std::string& text) {
    const auto end = text.find(". ");
    return end == std::string::npos ? text : text.substr(0, end);
  };
  auto row = [&](const runner::RealTimePlanResult& r) {
    return fmt::format("{:<26} {:>10} {:>10} {:>10} {:>12} {:>12}  {}", r.Label(),
                       num(r.J1_ms, " ms"), num(r.J2, " %"), num(r.J3, " %"),
                       num(1e3 * r.critical_delay, " ms"), num(1e3 * r.remaining_delay, " ms"),
                       r.ok ? (r.unstable ? "finished, predicted UNSTABLE" : "stable")
                            : (r.unstable ? "UNSTABLE (predicted): " : "stopped: ") +
                                  first_sentence(r.failure));
  };
  runner::RealTimePlanOptions options;
  if (!opt.quiet) {
    fmt::print("hybridtest plan {}: a real-time run, its compensators and steps paced in virtual "
               "time on the emulated plant\n{:<26} {:>10} {:>10} {:>10} {:>12} {:>12}\n",
               opt.config, "compensator, step", "J1", "J2", "J3", "critical", "remaining");
    options.on_result = [&](std::size_t, std::size_t, const runner::RealTimePlanResult& r) {
      fmt::print("{}\n", row(r));
      std::fflush(stdout);
    };
  }
  const auto results = runner::PlanRealTime(opt.config, options);
  const auto best = runner::RecommendRealTime(results);
  if (!best) {
    fmt::print("no candidate finished stable: the plant's delay exceeds what these compensators "
               "remove; see docs/real-time.md (the stability check)\n");
    return;
  }
  fmt::print("\nrecommended (stable, smallest J2): {}  J1 {}, J2 {}, J3 {}, margin {} (critical "
             "delay {} against {} left)\n", best->Label(), num(best->J1_ms, " ms"),
             num(best->J2, " %"), num(best->J3, " %"),
             num(1e3 * (best->critical_delay - best->remaining_delay), " ms"),
             num(1e3 * best->critical_delay, " ms"), num(1e3 * best->remaining_delay, " ms"));
  fmt::print("\nin the config:\n{}\n", runner::RealTimeCandidateYaml(opt.config, *best));
}

void ExecutePlan(const PlanCommandOptions& opt) {
  if (!(opt.tolerance > 0.0)) {
    throw ConfigError(fmt::format("--tolerance {}: expected a positive relative error, e.g. "
                                  "0.01 for 1 %", opt.tolerance));
  }
  if (opt.overwrite && opt.keep.empty()) {
    throw ConfigError("--overwrite: replaces the files of an earlier plan in the --keep folder; "
                      "give --keep DIR, or leave --overwrite out (without --keep, plan writes "
                      "nothing)");
  }
  // With --emulate, the configured transfer systems are never read: the bench file stands in.
  io::SubstructureOptions substructure_options;
  if (!opt.emulate.empty()) substructure_options.emulate_bench = opt.emulate;
  const io::RunSpec spec = io::LoadRunSpec(opt.config, substructure_options);
  if (spec.real_time.enabled && opt.emulate.empty()) return ExecuteRealTimePlan(opt);
  runner::PlanOptions options;
  options.tolerance = opt.tolerance;
  if (!opt.emulate.empty()) options.emulate_bench = opt.emulate;
  options.work_dir = opt.keep;  // each run opened through the front door, as `run`'s
  options.overwrite = opt.overwrite;
  options.command_line = command_line();
  options.seeds.clear();
  for (int k = 1; k <= opt.seeds; ++k) options.seeds.push_back(static_cast<unsigned long>(k));
  const std::string header =
      fmt::format("{:<48} {:>11} {:>11} {:>10} {:>9} {:>11}", "scheme", "evaluations",
                  "lab time", "error", "reversals", "force rev.");
  std::vector<runner::PlanWarning> warnings;
  options.on_warnings = [&](const std::vector<runner::PlanWarning>& w) {
    warnings = w;
    for (const auto& x : w) fmt::print("warning: {}\n", x.message);
    if (!opt.quiet) {
      fmt::print("hybridtest plan {}: candidate schemes on emulated specimens against RK4 at "
                 "0.1 ms (error: max slot-displacement difference / peak-to-peak of the first "
                 "physical slot after 20 % of the run; where the bench has load-cell noise, "
                 "each row is the worst of {} noise seeds; reversals: of the command's "
                 "direction; force rev.: of the specimen force within moves)\n{}\n",
                 opt.config, opt.seeds, header);
    }
    std::fflush(stdout);
  };
  options.on_result = [&](std::size_t i, std::size_t n, const runner::PlanResult& r) {
    if (opt.quiet) return;
    fmt::print("{}   [{}/{}]\n", Row(r), i + 1, n);
    std::fflush(stdout);
  };
  const auto results = runner::PlanTest(spec, options);
  const auto best = runner::Recommend(results, opt.tolerance);
  if (!best) {
    fmt::print("no candidate met the tolerance of {} %.\n", 100.0 * opt.tolerance);
    if (!warnings.empty()) {
      fmt::print("The reference itself passes a safety limit (see the warning above): no scheme "
                 "can run this test as configured.\n");
      return;
    }
    bool reversed = false;
    for (const auto& r : results) {
      if (const std::string advice = runner::ForceReversalAdvice(r); !advice.empty() && r.ok) {
        if (!reversed) fmt::print("{}\n", advice);
        reversed = true;
      }
    }
    if (!reversed) {
      fmt::print("Tighten the steps (smaller dt or adaptive tolerance), or check the "
                 "specimen's K0 (initial_stiffness: measure)\n");
    }
    return;
  }
  fmt::print("\nrecommended (fewest specimen evaluations with error ≤ {} %): {}\n  {} "
             "evaluations, lab time {} (the configured scheme: {}), error {:.3f} %\n{}",
             100.0 * opt.tolerance, best->candidate.label, best->evaluations,
             Duration(best->lab_time),
             results.front().ok ? Duration(results.front().lab_time) : std::string("failed"),
             100.0 * best->error, runner::IntegratorYaml(best->candidate));
  if (const std::string advice = runner::ForceReversalAdvice(*best); !advice.empty()) {
    fmt::print("note: {}\n", advice);
  }
  fmt::print("\nthe configured test with this scheme, complete (save it beside {} and run it):\n"
             "---\n{}", opt.config, RecommendedConfig(spec, best->candidate));
}

void AddPlanCommand(CLI::App& root) {
  auto opt = std::make_shared<PlanCommandOptions>();
  CLI::App* cmd = root.add_subcommand(
      "plan", "Before a test: compare schemes on emulated specimens (evaluations, lab time, "
              "error) and recommend the cheapest that meets a tolerance; moves no real bench");
  cmd->add_option("config", opt->config, "run configuration (YAML)")->required();
  cmd->add_option("--tolerance", opt->tolerance,
                  "largest acceptable error, relative to the specimen's peak-to-peak (default "
                  "0.01 = 1 %)")
      ->check(PositiveFiniteNumber());
  cmd->add_option("--emulate", opt->emulate,
                  "emulated bench config that stands in for physical slots on other transfer "
                  "systems (remote, modbus, ...)");
  cmd->add_option("--keep", opt->keep,
                  "also write every run's files into this folder (without it, plan writes "
                  "nothing: runs are held in memory)");
  cmd->add_flag("--overwrite", opt->overwrite,
               "with --keep: replace the files of an earlier plan in that folder (without it, "
               "plan refuses to write over them)");
  cmd->add_option("--seeds", opt->seeds,
                  "load-cell noise seeds per candidate where the bench has noise (1..N; each "
                  "row reports the worst; default 3)")
      ->check(CLI::Range(1, 100));
  cmd->add_flag("--quiet", opt->quiet, "print only the recommendation");
  cmd->callback([opt] { ExecutePlan(*opt); });
}

const CommandRegistration kCommandPlanRegistration{"plan", &AddPlanCommand};

}  // namespace
}  // namespace hybridtest::app
