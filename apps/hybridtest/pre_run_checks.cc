// See pre_run_checks.h.
#include "pre_run_checks.h"

#include <fmt/core.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <complex>
#include <limits>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/constitutive/parse_law.h"
#include "hybridtest/integrators/stability.h"
#include "hybridtest/multibody/data.h"
#include "hybridtest/multibody/kane.h"
#include "hybridtest/schemes/step_control.h"
#include "hybridtest/substructures/physical_substructure.h"
#include "hybridtest/transfer/limits_check.h"

namespace hybridtest::app {

std::vector<double> SlotStiffnessForStability(const io::SimulationConfig& cfg) {
  const auto& slots = cfg.model.model.slots();
  std::vector<double> k(cfg.model.slot_stiffness.begin(), cfg.model.slot_stiffness.end());
  k.resize(slots.size(), 0.0);
  const YAML::Node section = cfg.input.root()["substructures"];
  if (!section.IsDefined() || !section.IsMap()) return k;
  for (std::size_t s = 0; s < slots.size(); ++s) {
    const YAML::Node node = section[slots[s].info.name];
    if (!node.IsDefined() || !node.IsMap()) continue;
    const std::string where = "substructures." + slots[s].info.name;
    if (node["law"]) {
      k[s] = constitutive::ParseRestoringForceLaw(node["law"], where + ".law")->initial_stiffness();
    } else if (node["safety"] && node["safety"].IsMap() && node["safety"]["initial_stiffness"]) {
      k[s] = cfg.input.PositiveNumber(node["safety"]["initial_stiffness"],
                                      where + ".safety.initial_stiffness", "a stiffness in N/m");
    }
  }
  return k;
}

double CheckStepStability(const io::SimulationConfig& cfg) {
  const multibody::Model& model = cfg.model.model;
  const int n = model.num_coordinates();
  const int m = model.num_slots();
  const int nx = model.num_states();
  if (nx > multibody::kMaxDerivatives) return std::numeric_limits<double>::infinity();
  const std::vector<double> k = SlotStiffnessForStability(cfg);
  const Eigen::VectorXd& x0 = cfg.x0;
  multibody::Data<double> data(model);

  // Slot displacements d(q) and the restoring forces r = K d at the initial state.
  const auto displacements = [&](const Eigen::VectorXd& q) {
    Eigen::VectorXd d(m);
    multibody::CalcSlotDisplacements<double>(model, data, 0.0, q, d);
    return d;
  };
  const Eigen::VectorXd q0 = x0.head(n);
  Eigen::VectorXd r0 = displacements(q0);
  for (int i = 0; i < m; ++i) r0(i) *= k[i];

  // J, then ∂f/∂r = [0; M⁻¹ B] (B the exact coupling matrix), then ∂d/∂q (the schemes' slot
  // Jacobian, central differences).
  Eigen::MatrixXd jacobian = multibody::CalcStateJacobian(model, 0.0, x0, r0);
  if (m > 0) {
    Eigen::VectorXd xdot(nx), q_scratch(n), d_plus(m), d_minus(m);
    multibody::CalcStateDerivative<double>(model, data, 0.0, x0, r0, xdot);  // fills data.M
    Eigen::MatrixXd f_r = Eigen::MatrixXd::Zero(nx, m);  // the rates ż do not read r
    f_r.middleRows(n, n) = data.M.llt().solve(multibody::CalcCouplingMatrix(model, 0.0, x0));
    Eigen::MatrixXd d_q;
    schemes::CalcSlotJacobian(model, data, 0.0, q0, d_q, q_scratch, d_plus, d_minus);
    const Eigen::VectorXd kv = Eigen::Map<const Eigen::VectorXd>(k.data(), m);
    jacobian.leftCols(n) += f_r * kv.asDiagonal() * d_q;
  }

  // Modes, and the largest step the tableau keeps stable for all of them.
  const Eigen::VectorXcd eig = Eigen::EigenSolver<Eigen::MatrixXd>(jacobian, false).eigenvalues();
  const std::vector<std::complex<double>> modes(eig.data(), eig.data() + eig.size());
  std::complex<double> limiting;
  const double h_max = integrators::LargestStableStep(cfg.tableau, modes, &limiting);
  if (cfg.dt > h_max) {
    const YAML::Node dt_node = cfg.input.root()["integrator"]["dt"];
    throw ConfigError(fmt::format(
        "{} = {} s is beyond the stability limit of {} at the initial state: the largest "
        "stable step is {:.4g} ms (set by the mode λ = {:.4g} {:+.4g}i 1/s, |λ| = {:.4g} 1/s); "
        "the results would diverge. Choose dt ≤ {:.4g} s, or a scheme with a larger stability "
        "region (e.g. rk4)",
        cfg.input.Where(dt_node, "integrator.dt"), cfg.dt, cfg.tableau.name, h_max * 1e3,
        limiting.real(), limiting.imag(), std::abs(limiting), h_max));
  }
  return h_max;
}

}  // namespace hybridtest::app

namespace hybridtest::app {

double CheckSchemeStability(const io::SimulationConfig& cfg) {
  switch (cfg.scheme.kind) {
    case schemes::SchemeKind::kRungeKutta:
      return CheckStepStability(cfg);
    case schemes::SchemeKind::kMrOs: {
      io::SimulationConfig substeps = cfg;  // cfg.tableau is RK4 for operator splitting
      substeps.dt = cfg.scheme.substep;
      try {
        return CheckStepStability(substeps);
      } catch (const ConfigError& e) {
        throw ConfigError(fmt::format("integrator.substep (MR-OS's RK4 substeps): {}", e.what()));
      }
    }
    case schemes::SchemeKind::kAlphaOs:
      break;
  }
  return std::numeric_limits<double>::infinity();
}

namespace {

// " (about 1000 times ...: ...)" when a/b is near 1000 or 1/1000; empty otherwise.
std::string P0SlipHint(double runner, double bench) {
  if (runner == 0.0 || bench == 0.0) return "";
  const double ratio = std::abs(runner / bench);
  if (ratio > 300 && ratio < 3000) {
    return " (about 1000 times the bench's: a p0 in mm typed into setup.p0, which is in m?)";
  }
  if (ratio > 1.0 / 3000 && ratio < 1.0 / 300) {
    return " (about 1/1000 of the bench's: the bench's p0_mm given in m?)";
  }
  return "";
}

}  // namespace

void CheckPhysicalSlotsBeforeMoving(
    const io::SimulationConfig& cfg,
    const std::vector<std::unique_ptr<substructures::Substructure>>& subs) {
  const auto& slots = cfg.model.model.slots();
  for (std::size_t s = 0; s < subs.size() && s < slots.size(); ++s) {
    const auto* physical = dynamic_cast<const substructures::PhysicalSubstructure*>(subs[s].get());
    if (physical == nullptr) continue;
    const std::string where = "substructures." + slots[s].info.name;
    const transfer::BenchAnnouncement announced = physical->transfer().Announce();
    const transfer::SafetyLimits& limits = physical->safety().limits();
    if (announced.p0) {
      const double runner = physical->setup().p0, bench = *announced.p0;
      const double tolerance = kP0Tolerance * limits.max_increment;
      if (std::abs(runner - bench) > tolerance) {
        throw ConfigError(fmt::format(
            "{}.setup.p0 = {} m, but {} announces p0 = {} m (p0_mm: {}), its zero-force "
            "position{}: {} m apart (more than {} m, a tenth of safety.max_increment), the test "
            "would start with a jump or a loaded specimen. Nothing was sent to the bench. Set "
            "{}.setup.p0: {} (the bench's p0_mm / 1000), or correct the bench's p0_mm",
            where, runner, announced.source, bench, bench * 1e3, P0SlipHint(runner, bench),
            std::abs(runner - bench), tolerance, where, bench));
      }
    }
    if (announced.limits) {
      transfer::CheckLimitsAgainstBench(limits, *announced.limits, where + ".safety",
                                        announced.source);
    }
  }
}

}  // namespace hybridtest::app
