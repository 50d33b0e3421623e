// See run_spec.h and run_spec_yaml.h.
#include "hybridtest/io/run_spec.h"

#include <fmt/core.h>

#include <cmath>
#include <filesystem>

#include "hybridtest/common/error.h"
#include "hybridtest/io/run_spec_yaml.h"

namespace hybridtest::io {

long StepCount(double duration, double dt, bool whole) {
  if (!(dt > 0.0) || !(duration > 0.0)) {
    throw ConfigError(fmt::format("run spec: dt = {} s, duration = {} s: expected a positive "
                                  "step and duration", dt, duration));
  }
  const double ratio = duration / dt;
  if (!(ratio <= static_cast<double>(kMaxSteps))) {
    throw ConfigError(fmt::format("run spec: duration {} s with dt = {} s gives {:.3g} steps; at "
                                  "most {} are allowed: shorten the duration or enlarge dt",
                                  duration, dt, ratio, kMaxSteps));
  }
  const double steps = std::round(ratio);
  if (steps < 1.0) {
    throw ConfigError(fmt::format("run spec: duration {} s is shorter than one step of dt = {} s",
                                  duration, dt));
  }
  if (whole && std::abs(steps * dt - duration) > 1e-9 * duration) {
    throw ConfigError(fmt::format("run spec: duration {} s is not a whole number of steps of dt "
                                  "= {} s; choose a duration that is a multiple of dt",
                                  duration, dt));
  }
  return static_cast<long>(steps);
}

void ValidateRunSpec(const RunSpec& spec) {
  const multibody::Model& model = spec.model.model;
  if (spec.x0.size() != model.num_states()) {
    throw ConfigError(fmt::format("run spec: x0 has {} entries; the model '{}' needs {} "
                                  "([q; u; z])", spec.x0.size(), spec.model.name,
                                  model.num_states()));
  }
  bool blocks = false;  // a substructure serves several slots
  for (const auto& sub : spec.substructures) blocks = blocks || !sub.slots.empty();
  if (blocks) {
    std::vector<std::string> names;
    for (const auto& s : model.slots()) names.push_back(s.info.name);
    substructures::SlotIndices(spec.substructures, names);  // throws ConfigError
  } else {
    if (static_cast<int>(spec.substructures.size()) != model.num_slots()) {
      throw ConfigError(fmt::format("run spec: {} substructures for the {} slots of model '{}'; "
                                    "give one per slot, in slot order",
                                    spec.substructures.size(), model.num_slots(), spec.model.name));
    }
    for (int s = 0; s < model.num_slots(); ++s) {
      const std::string& name = model.slots()[static_cast<std::size_t>(s)].info.name;
      if (spec.substructures[static_cast<std::size_t>(s)].slot != name) {
        throw ConfigError(fmt::format("run spec: substructure {} is for slot '{}', but the model's "
                                      "slot {} is '{}'; give them in slot order", s,
                                      spec.substructures[static_cast<std::size_t>(s)].slot, s, name));
      }
    }
  }
  if (!(spec.scheme.dt > 0.0) || !(spec.scheme.duration > 0.0) || spec.scheme.steps < 1) {
    throw ConfigError(fmt::format("run spec: dt = {} s, duration = {} s, steps = {}: expected a "
                                  "positive step and duration and at least one step",
                                  spec.scheme.dt, spec.scheme.duration, spec.scheme.steps));
  }
  // A fixed-step run takes exactly `steps` steps: they must span the duration, or the run
  // would end early (or late) without a word.
  const long steps = StepCount(spec.scheme.duration, spec.scheme.dt,
                               !spec.scheme.config.adaptive.enabled);
  if (spec.scheme.steps != steps) {
    throw ConfigError(fmt::format(
        "run spec: scheme.steps = {}, but duration {} s / dt {} s = {} steps; the run would end "
        "at t = {} s instead of {} s: set scheme.steps = {} (io::StepCount(duration, dt)), or "
        "change dt or the duration",
        spec.scheme.steps, spec.scheme.duration, spec.scheme.dt, steps,
        static_cast<double>(spec.scheme.steps) * spec.scheme.dt, spec.scheme.duration, steps));
  }
  if (spec.output.files && spec.output.csv_path.empty()) {
    throw ConfigError("run spec: output.files is set but output.csv_path is empty: give the "
                      "journal's path, or set output.files = false for a run in memory");
  }
}

RunSpec CompileRunSpec(const SimulationConfig& cfg, const SubstructureOptions& options) {
  RunSpec spec(cfg.model);
  // The files read: the config and the model's (read when cfg was loaded), then what the
  // substructures' readers open.
  spec.source.files = cfg.files;
  SubstructureOptions reading = options;
  reading.files_read = &spec.source.files;
  spec.substructures = ParseSubstructureSpecs(cfg, reading);
  spec.x0 = cfg.x0;
  spec.scheme = {cfg.scheme, cfg.tableau, cfg.dt, cfg.duration, cfg.steps};
  spec.scheme.dt_where = cfg.input.Where(cfg.input.root()["integrator"]["dt"], "integrator.dt");
  spec.resume = {cfg.resume_force_tolerance, cfg.resume_position_tolerance};
  spec.start_ramp = cfg.start_ramp;
  spec.source.config_path = cfg.input.path();
  spec.source.config_text = cfg.input.text();
  spec.source.name = std::filesystem::path(cfg.input.path()).stem().string();
  spec.source.blades = cfg.blades;
  spec.source.bench_address = options.bench_address.value_or("");
  spec.output.csv_path =
      !cfg.output_csv.empty() ? cfg.output_csv : "results/" + spec.source.name + ".csv";
  spec.quiet = cfg.quiet;
  spec.source.test = cfg.test;
  spec.real_time = ReadRealTime(cfg.input);
  return spec;
}

RunSpec LoadRunSpec(const std::string& path, const SubstructureOptions& options) {
  return CompileRunSpec(LoadSimulationConfig(path), options);
}

}  // namespace hybridtest::io
