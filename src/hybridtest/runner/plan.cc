// See plan.h.
#include "hybridtest/runner/plan.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "hybridtest/common/error.h"
#include "hybridtest/constitutive/linear_spring.h"
#include "hybridtest/integrators/catalogue.h"
#include "hybridtest/io/substructure_config.h"
#include "hybridtest/io/transfer_readers.h"
#include "hybridtest/multibody/kane.h"
#include "hybridtest/runner/open_run.h"
#include "hybridtest/runner/run_record.h"
#include "hybridtest/runner/session.h"
#include "hybridtest/substructures/numerical_substructure.h"
#include "hybridtest/substructures/slot_law.h"
#include "hybridtest/substructures/substructure_spec.h"
#include "hybridtest/substructures/twin.h"
#include "hybridtest/transfer/emulated_bench.h"

namespace hybridtest::runner {
namespace {

namespace fs = std::filesystem;

constexpr double kReferenceStep = 1e-4;  // [s] RK4

// Direction reversals of a sequence of commands.
long Reversals(const std::vector<double>& c) {
  long reversals = 0;
  double last_sign = 0.0;
  for (std::size_t k = 1; k < c.size(); ++k) {
    const double d = c[k] - c[k - 1];
    if (d == 0.0 || !std::isfinite(d)) continue;
    const double sign = d > 0.0 ? 1.0 : -1.0;
    if (last_sign != 0.0 && sign != last_sign) ++reversals;
    last_sign = sign;
  }
  return reversals;
}

// What plan keeps of a run, in memory: the committed rows (as the journal would hold them)
// and the command of one physical slot at every trial (as the stage record would).
class PlanRecorder final : public SessionObserver {
 public:
  explicit PlanRecorder(int command_exchange) : command_exchange_(command_exchange) {}
  void OnTrial(const TrialEvent& e) override {
    for (const auto& x : e.exchanges) force_reversals += x.force_reversals;
    if (command_exchange_ >= 0 && static_cast<std::size_t>(command_exchange_) < e.exchanges.size()) {
      commands.push_back(e.exchanges[static_cast<std::size_t>(command_exchange_)].command);
    }
  }
  void OnCommit(const CommitEvent& e) override {
    if (e.kind == RowKind::kUncommitted) return;
    width = e.row.size();
    values.insert(values.end(), e.row.begin(), e.row.end());
  }
  // The rows as a run read back from its journal.
  io::RunData Data(const Session& session) const {
    io::RunData data;
    data.channels = JournalChannels(session.spec());
    const auto rows = static_cast<Eigen::Index>(width == 0 ? 0 : values.size() / width);
    data.values = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic,
                                                 Eigen::RowMajor>>(
        values.data(), rows, static_cast<Eigen::Index>(width));
    return data;
  }
  std::vector<double> commands;
  long force_reversals = 0;
  std::vector<double> values;
  std::size_t width = 0;

 private:
  int command_exchange_;
};

io::RunSpec WithScheme(const io::RunSpec& spec, const PlanCandidate& c) {
  io::RunSpec out = spec;
  out.scheme.config = c.scheme;
  out.scheme.tableau = c.tableau;
  out.scheme.dt = c.dt;
  out.scheme.steps = static_cast<long>(std::llround(spec.scheme.duration / c.dt));
  return out;
}

// Runs `spec` in memory (or into work_dir/<name>.csv, through the front door, when a work
// folder is given); returns the session's result and fills the recorder. Throws the run's error.
RunStatistics RunInMemory(io::RunSpec spec, const PlanOptions& options, const std::string& name,
                          PlanRecorder& recorder, io::RunData* data) {
  const std::string& work_dir = options.work_dir;
  spec.output.files = !work_dir.empty();
  spec.output.command = "plan";
  if (spec.output.files) spec.output.csv_path = (fs::path(work_dir) / (name + ".csv")).string();
  spec.quiet = true;
  OpenedRun opened =
      OpenRun(spec, {.overwrite = options.overwrite, .command_line = options.command_line});
  Session session(std::move(spec), std::move(opened));
  session.AddObserver(recorder);
  const StepResult r = session.Run();
  if (r.status != SessionStatus::kFinished) std::rethrow_exception(session.error());
  if (data != nullptr) *data = recorder.Data(session);
  return session.statistics();
}

// A candidate run once per seed; the worst of them.
void RunCandidate(const std::vector<io::RunSpec>& seeded, const PlanCandidate& candidate,
                  const multibody::Model& model, const io::RunData& reference,
                  int first_physical, const PlanOptions& options, const std::string& name,
                  PlanResult& res) {
  res.ok = true;
  for (std::size_t k = 0; k < seeded.size(); ++k) {
    io::RunSpec run_spec = WithScheme(seeded[k], candidate);
    // Operator splitting needs K0: measure it (on the emulated bench) where none is given.
    if (candidate.scheme.kind != schemes::SchemeKind::kRungeKutta) {
      for (auto& sub : run_spec.substructures) {
        auto& physical = sub.physical;
        if (physical && !physical->initial_stiffness && !physical->safety_stiffness &&
            !physical->stiffness_ramp) {
          physical->stiffness_ramp = 1e-3;
        }
      }
    }
    const std::string run_name = seeded.size() > 1 ? fmt::format("{}-seed{}", name, k + 1) : name;
    try {
      PlanRecorder recorder(0);  // the first physical slot's exchange
      io::RunData run;
      const RunStatistics stats =
          RunInMemory(std::move(run_spec), options, run_name, recorder, &run);
      res.evaluations = std::max(res.evaluations, stats.physical_evaluations);
      res.lab_time = std::max(res.lab_time, stats.lab_time);
      res.wall_time += stats.wall_time;
      res.error = std::max(res.error, RelativeError(model, run, reference, first_physical));
      res.reversals = std::max(res.reversals, Reversals(recorder.commands));
      res.force_reversals = std::max(res.force_reversals, recorder.force_reversals);
    } catch (const std::exception& e) {
      res.ok = false;
      res.failure = seeded.size() > 1 ? fmt::format("(run {} of {}) {}", k + 1, seeded.size(), e.what())
                                      : std::string(e.what());
    }
    res.runs = static_cast<int>(k + 1);
    if (!res.ok) return;
  }
}

}  // namespace

std::vector<PlanCandidate> DefaultCandidates(const io::RunSpec& spec, double p2p) {
  std::vector<PlanCandidate> out;
  const auto rk4 = integrators::FindTableau("rk4");
  const io::SchemeSpec& configured = spec.scheme;
  out.push_back({fmt::format("as configured ({}{})", schemes::SchemeKindName(configured.config.kind),
                             configured.config.kind == schemes::SchemeKind::kRungeKutta
                                 ? " " + configured.tableau.name +
                                       fmt::format(", dt {} s", configured.dt)
                                 : ""),
                 configured.config, configured.tableau, configured.dt});
  // Fixed steps must divide the duration.
  auto divides = [&](double dt) {
    const double n = std::round(spec.scheme.duration / dt);
    return n >= 1.0 && std::abs(n * dt - spec.scheme.duration) <= 1e-9 * spec.scheme.duration;
  };
  const auto heun = integrators::FindTableau("heun");
  const bool configured_is_paper = configured.config.kind == schemes::SchemeKind::kRungeKutta &&
                                   configured.tableau.name == heun.name && configured.dt == 1e-3;
  if (!configured_is_paper && divides(1e-3)) {
    out.push_back({"baseline: the paper's scheme (heun, dt 0.001 s)", {}, heun, 1e-3});
  }
  auto make = [&](schemes::SchemeKind kind, double dt, double rel_tol) {
    PlanCandidate c;
    c.scheme.kind = kind;
    c.tableau = rk4;
    c.dt = dt;
    if (rel_tol > 0.0) {
      c.scheme.adaptive.enabled = true;
      c.scheme.adaptive.tolerance = rel_tol * p2p;
      c.scheme.adaptive.dt_min = kind == schemes::SchemeKind::kMrOs ? 0.005 : 0.001;
      c.scheme.adaptive.dt_max = kind == schemes::SchemeKind::kMrOs ? 0.2 : 0.05;
      c.label = fmt::format("{} adaptive, tolerance {:.2g} m", schemes::SchemeKindName(kind),
                            c.scheme.adaptive.tolerance);
    } else {
      c.label = fmt::format("{}, dt {} s", schemes::SchemeKindName(kind), dt);
    }
    out.push_back(c);
  };
  for (double dt : {0.005, 0.0025}) {
    if (divides(dt)) make(schemes::SchemeKind::kAlphaOs, dt, 0.0);
  }
  for (double tol : {1e-4, 2.5e-5}) make(schemes::SchemeKind::kAlphaOs, 0.005, tol);
  for (double dt : {0.02}) {
    if (divides(dt)) make(schemes::SchemeKind::kMrOs, dt, 0.0);
  }
  for (double tol : {1e-3, 2.7e-4, 7e-5}) make(schemes::SchemeKind::kMrOs, 0.01, tol);
  return out;
}

double RelativeError(const multibody::Model& model, const io::RunData& run,
                     const io::RunData& reference, int first_physical_slot, double* p2p_out) {
  const int n = model.num_coordinates();
  const int m = model.num_slots();
  multibody::Data<double> data(model);
  // Slot displacements of every row of a run: (rows × m).
  auto displacements = [&](const io::RunData& r) {
    Eigen::MatrixXd d(r.num_rows(), m);
    Eigen::VectorXd q(n), ds(m);
    std::vector<Eigen::VectorXd> cols;
    for (const auto& c : model.coordinates()) cols.push_back(r.Get(c.name));
    const Eigen::VectorXd t = r.Get("t");
    for (long k = 0; k < r.num_rows(); ++k) {
      for (int i = 0; i < n; ++i) q(i) = cols[static_cast<std::size_t>(i)](k);
      multibody::CalcSlotDisplacements<double>(model, data, t(k), q, ds);
      d.row(k) = ds.transpose();
    }
    return d;
  };
  const Eigen::VectorXd t_ref = reference.Get("t");
  const Eigen::VectorXd t_run = run.Get("t");
  const Eigen::MatrixXd d_ref = displacements(reference);
  const Eigen::MatrixXd d_run = displacements(run);
  const double t_end = t_ref(t_ref.size() - 1);
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (Eigen::Index k = 0; k < t_ref.size(); ++k) {
    if (t_ref(k) < 0.2 * t_end) continue;
    lo = std::min(lo, d_ref(k, first_physical_slot));
    hi = std::max(hi, d_ref(k, first_physical_slot));
  }
  const double p2p = hi - lo;
  if (p2p_out != nullptr) *p2p_out = p2p;
  double worst = 0.0;
  Eigen::Index j = 0;
  for (Eigen::Index k = 0; k < t_run.size(); ++k) {
    const double t = t_run(k);
    while (j + 2 < t_ref.size() && t_ref(j + 1) < t) ++j;
    const double w = std::clamp((t - t_ref(j)) / (t_ref(j + 1) - t_ref(j)), 0.0, 1.0);
    for (int s = 0; s < m; ++s) {
      const double ref = (1.0 - w) * d_ref(j, s) + w * d_ref(j + 1, s);
      const double e = std::abs(d_run(k, s) - ref);
      worst = std::isnan(e) ? std::numeric_limits<double>::infinity() : std::max(worst, e);
    }
  }
  return p2p > 0.0 ? worst / p2p : std::numeric_limits<double>::infinity();
}

std::vector<PlanResult> PlanTest(const io::RunSpec& configured, const PlanOptions& options) {
  io::RunSpec spec = configured;
  const multibody::Model& model = spec.model.model;
  // Which slots are physical, and is each one emulated (no steel may move in a plan)?
  int first_physical = -1;
  for (std::size_t s = 0; s < spec.substructures.size(); ++s) {
    auto& physical = spec.substructures[s].physical;
    if (!physical) continue;
    if (first_physical < 0) {  // the model index of the substructure's first slot
      const std::string first_slot = spec.substructures[s].SlotNames().front();
      for (int i = 0; i < model.num_slots(); ++i) {
        if (model.slots()[static_cast<std::size_t>(i)].info.name == first_slot) first_physical = i;
      }
    }
    if (options.emulate_bench) {
      physical->transfer = io::EmulatedTransfer(*options.emulate_bench);
    } else if (physical->transfer.type != "emulated" && physical->transfer.type != "fmu") {
      // (an FMU plant, fmi/fmu_plant.h, is in-process: a model, no steel)
      throw ConfigError(fmt::format(
          "{}: plan never moves a real bench, and slot {} is not on an emulated one (built-in or an FMU plant); give "
          "--emulate BENCH.yaml (an emulated bench config, e.g. examples/rotor/"
          "bench-cantilever.yaml) to stand in for it", spec.source.config_path,
          spec.substructures[s].slot));
    }
  }
  if (first_physical < 0) {
    throw ConfigError(fmt::format("{}: has no physical substructure; plan compares schemes by "
                                  "their specimen evaluations, so it needs one (a `type: "
                                  "physical` slot on an emulated bench)", spec.source.config_path));
  }
  if (!options.work_dir.empty()) fs::create_directories(options.work_dir);

  // The reference: numerical twins of the specimens, RK4 at 0.1 ms.
  PlanCandidate ref_candidate{"reference", {}, integrators::FindTableau("rk4"), kReferenceStep};
  io::RunSpec ref_spec = WithScheme(spec, ref_candidate);
  for (std::size_t s = 0; s < ref_spec.substructures.size(); ++s) {
    if (!ref_spec.substructures[s].physical) continue;
    const auto built = ref_spec.substructures[s].Build();
    const std::string slot = ref_spec.substructures[s].slot;
    substructures::SubstructureSpec twin;
    twin.slot = slot;
    twin.slots = ref_spec.substructures[s].slots;
    if (auto block = substructures::EmulatedBlockTwin(*built)) {
      // A specimen law in actuator coordinates (e.g. the biaxial Bouc–Wen): r = Tᵀ F(T d),
      // or r = J(d)ᵀ F(ℓ(d) − L0) through a large-displacement setup.
      twin.block_law = block->block_law;
      twin.block_transform = block->block_transform;
      twin.block_setup = block->block_setup;
    } else if (auto k = substructures::TwinStiffness(*built, slot)) {
      twin.stiffness = std::move(*k);
    } else {
      twin.law = substructures::TwinLaw(*built, slot);
    }
    ref_spec.substructures[s] = std::move(twin);
  }
  io::RunData reference;
  {
    PlanRecorder recorder(-1);
    RunInMemory(ref_spec, options, "reference", recorder, &reference);
  }
  double p2p = 0.0;
  RelativeError(model, reference, reference, first_physical, &p2p);
  const std::vector<PlanWarning> warnings = ReferenceLimitWarnings(spec, reference);
  if (options.on_warnings) options.on_warnings(warnings);

  const std::vector<io::RunSpec> seeded = SeededSpecs(spec, options.seeds);
  const std::vector<PlanCandidate> candidates = DefaultCandidates(spec, p2p);
  std::vector<PlanResult> results;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    PlanResult res;
    res.candidate = candidates[i];
    RunCandidate(seeded, candidates[i], model, reference, first_physical, options,
                 fmt::format("candidate-{}", i), res);
    if (options.on_result) options.on_result(i, candidates.size(), res);
    results.push_back(std::move(res));
  }
  return results;
}

std::optional<PlanResult> Recommend(const std::vector<PlanResult>& results, double tolerance) {
  std::optional<PlanResult> best;
  for (const auto& r : results) {
    if (!r.ok || !(r.error <= tolerance)) continue;
    if (!best || r.evaluations < best->evaluations ||
        (r.evaluations == best->evaluations && r.lab_time < best->lab_time)) {
      best = r;
    }
  }
  return best;
}

std::string IntegratorYaml(const PlanCandidate& c) {
  std::string y = fmt::format("integrator:\n  scheme: {}\n", schemes::SchemeKindName(c.scheme.kind));
  if (c.scheme.kind == schemes::SchemeKind::kRungeKutta) y += fmt::format("  tableau: {}\n", c.tableau.name);
  y += fmt::format("  dt: {}\n", c.dt);
  if (c.scheme.kind == schemes::SchemeKind::kAlphaOs) y += fmt::format("  alpha: {}\n", c.scheme.alpha);
  if (c.scheme.kind == schemes::SchemeKind::kMrOs) y += fmt::format("  substep: {}\n", c.scheme.substep);
  if (c.scheme.adaptive.enabled) {
    y += fmt::format("  adaptive: {{tolerance: {:.3g}, dt_min: {}, dt_max: {}}}\n",
                     c.scheme.adaptive.tolerance, c.scheme.adaptive.dt_min, c.scheme.adaptive.dt_max);
  }
  return y;
}

}  // namespace hybridtest::runner
