// See plan.h.
#include "hybridtest/runner/plan.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <random>

#include "hybridtest/common/error.h"
#include "hybridtest/constitutive/linear_spring.h"
#include "hybridtest/integrators/catalogue.h"
#include "hybridtest/io/substructure_config.h"
#include "hybridtest/multibody/kane.h"
#include "hybridtest/runner/hybrid_test.h"
#include "hybridtest/substructures/numerical_substructure.h"
#include "hybridtest/substructures/physical_substructure.h"
#include "hybridtest/transfer/emulated_bench.h"

namespace hybridtest::runner {
namespace {

namespace fs = std::filesystem;

constexpr double kReferenceStep = 1e-4;  // [s] RK4

// The emulated specimen's law behind a physical substructure, as a numerical one; or a linear
// spring of its K0 where the setup is not the identity or the bench is not emulated.
std::unique_ptr<substructures::Substructure> NumericalTwin(const substructures::Substructure& s,
                                                           const std::string& slot) {
  const auto* physical = dynamic_cast<const substructures::PhysicalSubstructure*>(&s);
  if (physical == nullptr) return nullptr;
  const auto* bench = dynamic_cast<const transfer::EmulatedBench*>(&physical->transfer());
  const auto& setup = physical->setup();
  const bool identity = setup.sign == 1.0 && setup.scale == 1.0 && setup.force_sign == 1.0 &&
                        setup.force_scale == 1.0 && setup.load_cell_zero == 0.0;
  if (bench != nullptr && identity && std::abs(setup.p0 - bench->config().p0) < 1e-12) {
    return std::make_unique<substructures::NumericalSubstructure>(
        bench->config().specimen->Clone());
  }
  const auto k0 = physical->initial_stiffness();
  if (!k0) {
    throw ConfigError(fmt::format("plan: slot {} has no emulated specimen law that the reference "
                                  "can use and no initial_stiffness; give "
                                  "substructures.{}.initial_stiffness in N/m", slot, slot));
  }
  return std::make_unique<substructures::NumericalSubstructure>(
      std::make_unique<constitutive::LinearSpring>(*k0, "plan reference (K0)"));
}

long Reversals(const std::string& stages_csv, const std::string& channel) {
  if (!fs::exists(stages_csv)) return 0;
  const io::RunData s = io::LoadRun(stages_csv);
  if (!s.Has(channel)) return 0;
  const Eigen::VectorXd c = s.Get(channel);
  long reversals = 0;
  double last_sign = 0.0;
  for (Eigen::Index k = 1; k < c.size(); ++k) {
    const double d = c(k) - c(k - 1);
    if (d == 0.0 || !std::isfinite(d)) continue;
    const double sign = d > 0.0 ? 1.0 : -1.0;
    if (last_sign != 0.0 && sign != last_sign) ++reversals;
    last_sign = sign;
  }
  return reversals;
}

io::SimulationConfig WithScheme(const io::SimulationConfig& cfg, const PlanCandidate& c) {
  io::SimulationConfig out = cfg;
  out.scheme = c.scheme;
  out.tableau = c.tableau;
  out.dt = c.dt;
  out.steps = static_cast<long>(std::llround(cfg.duration / c.dt));
  return out;
}

}  // namespace

std::vector<PlanCandidate> DefaultCandidates(const io::SimulationConfig& cfg, double p2p) {
  std::vector<PlanCandidate> out;
  const auto rk4 = integrators::FindTableau("rk4");
  out.push_back({fmt::format("as configured ({}{})", schemes::SchemeKindName(cfg.scheme.kind),
                             cfg.scheme.kind == schemes::SchemeKind::kRungeKutta
                                 ? " " + cfg.tableau.name + fmt::format(", dt {} s", cfg.dt)
                                 : ""),
                 cfg.scheme, cfg.tableau, cfg.dt});
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
  // Fixed steps must divide the duration.
  auto divides = [&](double dt) {
    const double n = std::round(cfg.duration / dt);
    return n >= 1.0 && std::abs(n * dt - cfg.duration) <= 1e-9 * cfg.duration;
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

std::vector<PlanResult> PlanTest(const io::SimulationConfig& cfg, const PlanOptions& options) {
  io::SubstructureOptions sub_options;
  sub_options.emulate_bench = options.emulate_bench;
  // Which slots are physical, and is each one emulated (no steel may move in a plan)?
  int first_physical = -1;
  {
    const auto subs = io::MakeSubstructures(cfg, sub_options);
    for (std::size_t s = 0; s < subs.size(); ++s) {
      const auto* p = dynamic_cast<const substructures::PhysicalSubstructure*>(subs[s].get());
      if (p == nullptr) continue;
      if (first_physical < 0) first_physical = static_cast<int>(s);
      if (dynamic_cast<const transfer::EmulatedBench*>(&p->transfer()) == nullptr &&
          !options.emulate_bench) {
        throw ConfigError(fmt::format(
            "{}: plan never moves a real bench, and slot {} is not on an emulated one; give "
            "--emulate BENCH.yaml (an emulated bench config, e.g. examples/rotor/"
            "bench-cantilever.yaml) to stand in for it", cfg.input.path(),
            cfg.model.model.slots()[s].info.name));
      }
    }
  }
  if (first_physical < 0) {
    throw ConfigError(fmt::format("{}: has no physical substructure; plan compares schemes by "
                                  "their specimen evaluations, so it needs one (a `type: "
                                  "physical` slot on an emulated bench)", cfg.input.path()));
  }

  const bool temporary = options.work_dir.empty();
  const fs::path dir = temporary ? fs::temp_directory_path() /
                                       fmt::format("hybridtest-plan-{}", std::random_device{}())
                                 : fs::path(options.work_dir);
  fs::create_directories(dir);
  struct Cleanup {
    fs::path dir;
    bool active;
    ~Cleanup() {
      std::error_code ec;
      if (active) fs::remove_all(dir, ec);
    }
  } cleanup{dir, temporary};

  RunOptions quiet;
  quiet.progress.mode = ProgressMode::kQuiet;
  quiet.command = "plan";

  // The reference: numerical twins of the specimens, RK4 at 0.1 ms.
  PlanCandidate ref_candidate{"reference", {}, integrators::FindTableau("rk4"), kReferenceStep};
  const io::SimulationConfig ref_cfg = WithScheme(cfg, ref_candidate);
  {
    auto subs = io::MakeSubstructures(cfg, sub_options);
    for (std::size_t s = 0; s < subs.size(); ++s) {
      if (auto twin = NumericalTwin(*subs[s], cfg.model.model.slots()[s].info.name)) {
        subs[s] = std::move(twin);
      }
    }
    RunOptions o = quiet;
    o.csv_path = (dir / "reference.csv").string();
    HybridTest(ref_cfg, std::move(subs), o).Run();
  }
  const io::RunData reference = io::LoadRun((dir / "reference.csv").string());
  double p2p = 0.0;
  RelativeError(cfg.model.model, reference, reference, first_physical, &p2p);

  const std::vector<PlanCandidate> candidates = DefaultCandidates(cfg, p2p);
  const std::string command_channel =
      cfg.model.model.slots()[static_cast<std::size_t>(first_physical)].info.name + "_command";
  std::vector<PlanResult> results;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    PlanResult res;
    res.candidate = candidates[i];
    const io::SimulationConfig run_cfg = WithScheme(cfg, candidates[i]);
    RunOptions o = quiet;
    o.csv_path = (dir / fmt::format("candidate-{}.csv", i)).string();
    try {
      auto subs = io::MakeSubstructures(run_cfg, sub_options);
      // Operator splitting needs K0: measure it (on the emulated bench) where none is given.
      for (auto& s : subs) {
        auto* p = dynamic_cast<substructures::PhysicalSubstructure*>(s.get());
        if (p != nullptr && !p->initial_stiffness() && !p->requested_stiffness_ramp() &&
            candidates[i].scheme.kind != schemes::SchemeKind::kRungeKutta) {
          p->RequestStiffnessMeasurement(1e-3);
        }
      }
      HybridTest test(run_cfg, std::move(subs), o);
      const RunStatistics stats = test.Run();
      res.ok = true;
      res.evaluations = stats.physical_evaluations;
      res.lab_time = stats.lab_time;
      res.wall_time = stats.wall_time;
      res.error = RelativeError(cfg.model.model, io::LoadRun(o.csv_path), reference, first_physical);
      res.reversals = Reversals((dir / fmt::format("candidate-{}.stages.csv", i)).string(),
                                command_channel);
    } catch (const std::exception& e) {
      res.ok = false;
      res.failure = e.what();
    }
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
