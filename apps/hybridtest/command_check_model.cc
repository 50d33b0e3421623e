// hybridtest check-model MODEL.yaml [--states N] [--seed S] [--no-sympy]
// Validates a model file (docs/model-files.md) and prints what it declares; checks that the
// mass matrix M is positive definite at random states; and, when python3 with SymPy is
// present, derives the same model independently with SymPy's KanesMethod from the same file
// and reports the worst relative difference of M and g; for a model with constraints, also its
// reduced equations with dependent speeds at consistent states (check_constraints_sympy.py).
// Exit status: 0 all checks pass, 2 the file is invalid (the message names file:line), 1 a
// check failed.
#include <fmt/core.h>
#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <cstdio>
#include <random>

#include "command.h"
#include "hybridtest/common/error.h"
#include "hybridtest/modelfile/model_file.h"
#include "hybridtest/multibody/kane.h"
#include "sympy_check.h"

namespace hybridtest::app {
namespace {

struct CheckModelOptions {
  std::string file;
  int states = 20;
  unsigned seed = 1;
  bool no_sympy = false;
  int sympy_states = 5;      // states compared with SymPy
  double tolerance = 1e-9;   // relative
  double sympy_timeout = 600.0;  // [s]
};

// The coordinates that take part in the direction `v` (an eigenvector of a singular M or W):
// those with at least 30 % of its largest component.
std::string CoordinatesIn(const multibody::Model& model, const Eigen::VectorXd& v) {
  std::string out;
  const double big = v.cwiseAbs().maxCoeff();
  for (int k = 0; k < v.size(); ++k) {
    if (std::abs(v(k)) >= 0.3 * big) {
      out += fmt::format("{}{}", out.empty() ? "" : ", ", model.coordinates()[k].name);
    }
  }
  return out;
}

// A random state: q_k within ±1 rad for angles, ±0.1 in other units; u within ±1; r within
// ±100 in the slot's unit; extra states z within ±1; t in [0, 2] s.
SympyState RandomState(const multibody::Model& model, std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const int n = model.num_coordinates();
  SympyState s{2.0 * std::abs(unit(rng)), Eigen::VectorXd(n), Eigen::VectorXd(n),
               Eigen::VectorXd(model.num_slots()), Eigen::VectorXd(model.num_extra_states())};
  for (int k = 0; k < n; ++k) {
    s.q(k) = (model.coordinates()[k].unit == "rad" ? 1.0 : 0.1) * unit(rng);
    s.u(k) = unit(rng);
  }
  for (int i = 0; i < model.num_slots(); ++i) s.r(i) = 100.0 * unit(rng);
  for (int i = 0; i < model.num_extra_states(); ++i) s.z(i) = unit(rng);
  return s;
}

void PrintSummary(const models::BuiltModel& built, const std::string& path) {
  const multibody::Model& m = built.model;
  fmt::print("model {}: {}\n  file: {}\n", built.name, built.description, path);
  fmt::print("  coordinates ({}):\n", m.num_coordinates());
  for (int k = 0; k < m.num_coordinates(); ++k) {
    fmt::print("    {:<10} [{}] {}   speed {} [{}]\n", m.coordinates()[k].name,
               m.coordinates()[k].unit, m.coordinates()[k].description, m.speeds()[k].name,
               m.speeds()[k].unit);
  }
  if (m.num_extra_states() > 0) {
    fmt::print("  extra states ({}), after q and u in the state x = [q; u; z]:\n",
               m.num_extra_states());
    for (const auto& z : m.extra_states()) {
      fmt::print("    {:<10} [{}] {} (initial {:g})\n", z.info.name, z.info.unit,
                 z.info.description, z.initial);
    }
  }
  fmt::print("  kinematical equations: {}\n",
             m.has_identity_kinematics() ? "q̇ = u" : "q̇ = W(q) u (from the file)");
  fmt::print("  restoring-force slots ({}):\n", m.num_slots());
  for (int s = 0; s < m.num_slots(); ++s) {
    const auto& info = m.slots()[s].info;
    fmt::print("    {:<10} [{}] {} (default numerical stiffness {:g} {})\n", info.name,
               info.unit, info.description, built.slot_stiffness[s],
               info.unit == "N" ? "N/m" : "N·m/rad");
  }
  double mass = 0.0;
  for (const auto& p : m.particles()) mass += p.mass;
  for (const auto& b : m.bodies()) mass += b.mass;
  fmt::print("  mass: {} particles, {} rigid bodies, total {:g} kg\n", m.particles().size(),
             m.bodies().size(), mass);
  fmt::print("  frames: {} (with N), points: {} (with O), loads: {}, time functions: {}\n",
             m.frames().size(), m.points().size(), m.loads().size(), m.time_functions().size());
  fmt::print("  parameters ({}):\n", built.parameters.all().size());
  for (const auto& p : built.parameters.all()) {
    fmt::print("    {:<12} {:>12g} {:<8} {}\n", p.name, p.value, p.unit, p.description);
  }
}

void RunCheckModel(const CheckModelOptions& opt) {
  const modelfile::ModelFile file = modelfile::LoadModelFile(opt.file);
  const models::BuiltModel built = modelfile::BuildModelFile(file, file.parameters);
  const multibody::Model& model = built.model;
  PrintSummary(built, opt.file);

  // M at random states: symmetric positive definite, and the engine's M and g kept for SymPy.
  std::mt19937 rng(opt.seed);
  multibody::Data<double> data(model);
  std::vector<SympyState> states;
  std::vector<Eigen::MatrixXd> M;
  std::vector<Eigen::VectorXd> g;
  std::vector<Eigen::VectorXd> xdot;
  double worst_ratio = 1.0;
  bool ok = true;
  for (int i = 0; i < opt.states; ++i) {
    const SympyState s = RandomState(model, rng);
    Eigen::VectorXd x(model.num_states());
    x << s.q, s.u, s.z;
    multibody::CalcKinematics<double>(model, data, s.t, x);
    multibody::CalcMassMatrix<double>(model, data);
    multibody::CalcForcing<double>(model, data, s.r);
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(data.M);
    const double lo = eig.eigenvalues().minCoeff(), hi = eig.eigenvalues().maxCoeff();
    if (!model.has_identity_kinematics()) {
      const Eigen::JacobiSVD<Eigen::MatrixXd> svd(data.W, Eigen::ComputeFullV);
      const Eigen::VectorXd sv = svd.singularValues();
      if (!(sv(sv.size() - 1) > 1e-12 * sv(0))) {
        fmt::print("check: W(q) of q̇ = W(q) u is singular at random state {} (q = [{}]) in the "
                   "direction of {}: the speeds cannot be found from q̇ there; choose other "
                   "coordinates or speeds (e.g. another Euler sequence)\n", i,
                   fmt::join(s.q.data(), s.q.data() + s.q.size(), ", "),
                   CoordinatesIn(model, svd.matrixV().col(sv.size() - 1)));
        ok = false;
        break;
      }
    }
    if (!(lo > 1e-12 * hi) || !data.g.allFinite()) {
      const std::string which =
          data.M.allFinite() ? CoordinatesIn(model, eig.eigenvectors().col(0)) : "(not finite)";
      fmt::print("check: M is not positive definite at random state {} (q = [{}]): eigenvalues "
                 "{:g} … {:g}; the direction of the smallest involves {}: give {} mass or "
                 "inertia, or check that the coordinates are not singular there\n", i,
                 fmt::join(s.q.data(), s.q.data() + s.q.size(), ", "), lo, hi, which,
                 which.find(',') == std::string::npos ? "it" : "them");
      ok = false;
      break;
    }
    Eigen::VectorXd xd(model.num_states());
    multibody::CalcStateDerivative<double>(model, data, s.t, x, s.r, xd);
    xdot.push_back(xd);
    worst_ratio = std::min(worst_ratio, lo / hi);
    states.push_back(s);
    M.push_back(data.M);
    g.push_back(data.g);
  }
  if (ok) {
    fmt::print("check: M symmetric positive definite at {} random states (smallest eigenvalue "
               "ratio {:.3g})  ok\n", states.size(), worst_ratio);
  }

  // SymPy: an independent reading of the same file.
  std::string why;
  std::optional<std::string> script;
  std::string python;
  if (opt.no_sympy) {
    fmt::print("sympy: skipped (--no-sympy)\n");
  } else if (!ok) {
    fmt::print("sympy: skipped (fix the mass matrix first)\n");
  } else if (!(script = FindSympyReader(&why)) || (python = FindPythonWithSympy(&why)).empty()) {
    fmt::print("sympy: skipped: {}\n", why);
  } else {
    const std::size_t count =
        std::min<std::size_t>(states.size(), static_cast<std::size_t>(std::max(1, opt.sympy_states)));
    fmt::print("sympy: deriving the model with KanesMethod at {} states (may take a minute for "
               "large models; --no-sympy skips it)...\n", count);
    std::fflush(stdout);
    const std::vector<SympyState> some(states.begin(), states.begin() + static_cast<long>(count));
    const SympyResult ref = RunSympyReader(python, *script, opt.file, some, opt.sympy_timeout);
    if (ref.M.size() != count || ref.g.size() != count || ref.qdot.size() != count ||
        ref.zdot.size() != count) {
      throw Error(fmt::format("the SymPy reader answered for {} states, not {}", ref.M.size(), count));
    }
    double worst_M = 0.0, worst_g = 0.0, worst_xdot = 0.0;
    for (std::size_t i = 0; i < count; ++i) {
      if (ref.M[i].rows() != M[i].rows() || ref.g[i].size() != g[i].size() ||
          ref.qdot[i].size() != g[i].size() || ref.zdot[i].size() != model.num_extra_states()) {
        throw Error("the SymPy reader returned matrices of another size than the engine's");
      }
      worst_M = std::max(worst_M, (ref.M[i] - M[i]).cwiseAbs().maxCoeff() /
                                      std::max(1e-300, ref.M[i].cwiseAbs().maxCoeff()));
      worst_g = std::max(worst_g, (ref.g[i] - g[i]).cwiseAbs().maxCoeff() /
                                      std::max(1.0, ref.g[i].cwiseAbs().maxCoeff()));
      // ẋ from SymPy's own M, g, q̇ = W(q) u and ż. A constrained model's ẋ solves the
      // reduced equations, which this reader does not form (tests/oracle/constraints_oracle.py
      // checks them): its tree M and g are compared, at these unconstrained states.
      if (model.has_constraints()) continue;
      Eigen::VectorXd x_ref(model.num_states());
      x_ref << ref.qdot[i], ref.M[i].ldlt().solve(ref.g[i]), ref.zdot[i];
      worst_xdot = std::max(worst_xdot, (x_ref - xdot[i]).cwiseAbs().maxCoeff() /
                                            std::max(1.0, x_ref.cwiseAbs().maxCoeff()));
    }
    const bool agree = worst_M < opt.tolerance && worst_g < opt.tolerance &&
                       worst_xdot < opt.tolerance;
    fmt::print("sympy: KanesMethod from the same file at {} states: worst relative difference "
               "M {:.3g}, g {:.3g}, ẋ {:.3g} (tolerance {:g})  {}\n", count, worst_M, worst_g,
               worst_xdot, opt.tolerance, agree ? "ok" : "DIFFERENT");
    ok = ok && agree;
    if (model.has_constraints()) {
      fmt::print("sympy: {} constraint rows: M and g above are the tree's (all speeds free); "
                 "now the reduced equations at {} consistent states...\n",
                 model.num_constraint_rows(), count);
      std::fflush(stdout);
      const ConstraintCheck c = RunConstraintCheck(python, *script, opt.file,
                                                   static_cast<int>(count), opt.seed,
                                                   opt.tolerance, opt.sympy_timeout);
      fmt::print("sympy: {}  {}\n", c.report, c.agree ? "ok" : "DIFFERENT");
      ok = ok && c.agree;
    }
  }
  if (!ok) throw Error(fmt::format("{}: the model file builds, but a check failed (above)", opt.file));
}

void AddCheckModelCommand(CLI::App& root) {
  auto opt = std::make_shared<CheckModelOptions>();
  CLI::App* cmd = root.add_subcommand(
      "check-model", "Validate a model file, summarise it and cross-check it against SymPy");
  cmd->add_option("model", opt->file, "model file (YAML, docs/model-files.md)")->required();
  cmd->add_option("--states", opt->states, "random states for the checks (default 20)");
  cmd->add_option("--seed", opt->seed, "random seed (default 1)");
  cmd->add_flag("--no-sympy", opt->no_sympy, "skip the SymPy cross-check");
  cmd->add_option("--sympy-states", opt->sympy_states,
                  "states compared with SymPy (default 5, at most --states)");
  cmd->add_option("--tolerance", opt->tolerance,
                  "largest relative difference from SymPy accepted (default 1e-9)");
  cmd->add_option("--sympy-timeout", opt->sympy_timeout,
                  "seconds the SymPy half may take (default 600; 0: no limit)");
  cmd->callback([opt] { RunCheckModel(*opt); });
}

const CommandRegistration kCommandCheckModelRegistration{"check-model", &AddCheckModelCommand};

}  // namespace
}  // namespace hybridtest::app
