// See pre_move_checks.h.
#include "hybridtest/runner/pre_move_checks.h"

#include <fmt/core.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <string>

#include "hybridtest/common/error.h"
#include "hybridtest/integrators/stability.h"
#include "hybridtest/multibody/data.h"
#include "hybridtest/multibody/constraints.h"
#include "hybridtest/multibody/kane.h"
#include "hybridtest/schemes/step_control.h"
#include "hybridtest/substructures/physical_substructure.h"
#include "hybridtest/transfer/limits_check.h"

namespace hybridtest::runner {

std::vector<double> SlotStiffnessForStability(const io::RunSpec& spec) {
  const auto& slots = spec.model.model.slots();
  std::vector<double> k(spec.model.slot_stiffness.begin(), spec.model.slot_stiffness.end());
  k.resize(slots.size(), 0.0);
  for (const auto& sub : spec.substructures) {
    if (!sub.slots.empty()) continue;  // several slots: their nominal stiffness
    std::size_t s = 0;
    while (s < slots.size() && slots[s].info.name != sub.slot) ++s;
    if (s == slots.size()) continue;
    if (sub.law) {
      k[s] = sub.law->initial_stiffness();
    } else if (sub.physical && sub.physical->safety_stiffness) {
      k[s] = *sub.physical->safety_stiffness;
    }
  }
  return k;
}

double CheckStepStability(const io::RunSpec& spec, double dt) {
  const multibody::Model& model = spec.model.model;
  const int n = model.num_coordinates();
  const int m = model.num_slots();
  const int nx = model.num_states();
  if (nx > multibody::kMaxDerivatives) return std::numeric_limits<double>::infinity();
  const std::vector<double> k = SlotStiffnessForStability(spec);
  const Eigen::VectorXd& x0 = spec.x0;
  multibody::Data<double> data(model);

  // Slot displacements d(q) and the restoring forces r = K d at the initial state.
  const Eigen::VectorXd q0 = x0.head(n);
  Eigen::VectorXd r0(m);
  multibody::CalcSlotDisplacements<double>(model, data, 0.0, q0, r0);
  for (int i = 0; i < m; ++i) r0(i) *= k[static_cast<std::size_t>(i)];

  // J, then ∂f/∂r = [0; M⁻¹ B] (B the exact coupling matrix), then ∂d/∂q (the schemes' slot
  // Jacobian, central differences).
  Eigen::MatrixXd jacobian = multibody::CalcStateJacobian(model, 0.0, x0, r0);
  if (m > 0) {
    Eigen::VectorXd xdot(nx), q_scratch(n), d_plus(m), d_minus(m);
    multibody::CalcStateDerivative<double>(model, data, 0.0, x0, r0, xdot);  // fills data.M
    Eigen::MatrixXd f_r = Eigen::MatrixXd::Zero(nx, m);  // the rates ż do not read r
    const Eigen::MatrixXd B_r = multibody::CalcCouplingMatrix(model, 0.0, x0);
    if (model.has_constraints()) {  // through the reduced equations (constraints.h)
      Eigen::MatrixXd dudr(n, m);
      multibody::CalcConstrainedRateCoupling(model, data, B_r, dudr);
      f_r.middleRows(n, n) = dudr;
    } else {
      f_r.middleRows(n, n) = data.M.llt().solve(B_r);
    }
    Eigen::MatrixXd d_q;
    schemes::CalcSlotJacobian(model, data, 0.0, q0, d_q, q_scratch, d_plus, d_minus);
    const Eigen::VectorXd kv = Eigen::Map<const Eigen::VectorXd>(k.data(), m);
    jacobian.leftCols(n) += f_r * kv.asDiagonal() * d_q;
  }

  // Modes, and the largest step the tableau keeps stable for all of them.
  const Eigen::VectorXcd eig = Eigen::EigenSolver<Eigen::MatrixXd>(jacobian, false).eigenvalues();
  const std::vector<std::complex<double>> modes(eig.data(), eig.data() + eig.size());
  std::complex<double> limiting;
  const integrators::ButcherTableau& tableau = spec.scheme.tableau;
  const double h_max = integrators::LargestStableStep(tableau, modes, &limiting);
  if (dt > h_max) {
    throw ConfigError(fmt::format(
        "{} = {} s is beyond the stability limit of {} at the initial state: the largest "
        "stable step is {:.4g} ms (set by the mode λ = {:.4g} {:+.4g}i 1/s, |λ| = {:.4g} 1/s); "
        "the results would diverge. Choose dt ≤ {:.4g} s, or a scheme with a larger stability "
        "region (e.g. rk4)",
        spec.scheme.dt_where, dt, tableau.name, h_max * 1e3, limiting.real(), limiting.imag(),
        std::abs(limiting), h_max));
  }
  return h_max;
}

double CheckSchemeStability(const io::RunSpec& spec) {
  switch (spec.scheme.config.kind) {
    case schemes::SchemeKind::kRungeKutta:
      return CheckStepStability(spec, spec.scheme.dt);
    case schemes::SchemeKind::kMrOs:
      try {  // the tableau is RK4 for operator splitting
        return CheckStepStability(spec, spec.scheme.config.substep);
      } catch (const ConfigError& e) {
        throw ConfigError(fmt::format("integrator.substep (MR-OS's RK4 substeps): {}", e.what()));
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
    const io::RunSpec& spec, const std::vector<std::unique_ptr<substructures::Substructure>>& subs) {
  for (std::size_t s = 0; s < subs.size() && s < spec.substructures.size(); ++s) {
    // Each actuator the bench tells about: its p0 and limits against the setup's.
    const substructures::Substructure& sub = *subs[s];
    const transfer::TransferSystem* t = sub.transfer_system();
    if (t == nullptr) continue;
    const transfer::BenchAnnouncement announced = t->Announce();
    const int n = std::min(sub.num_actuators(), static_cast<int>(announced.actuators.size()));
    for (int k = 0; k < n; ++k) {
      const auto p0 = sub.actuator_p0(k);
      const auto actuator_limits = sub.actuator_limits(k);
      if (!p0 || !actuator_limits) continue;
      const transfer::ActuatorAnnouncement& bench_actuator =
          announced.actuators[static_cast<std::size_t>(k)];
      const std::string where = "substructures." + spec.substructures[s].slot;
      // "setup.p0" for one actuator; "setup.p0[2]" (1-based, as in the config's list) else.
      const std::string index = sub.num_actuators() == 1 ? "" : fmt::format("[{}]", k + 1);
      const std::string actuator =
          sub.num_actuators() == 1 ? "" : fmt::format(" for actuator {}", k + 1);
      const transfer::SafetyLimits& limits = *actuator_limits;
      if (bench_actuator.p0) {
        const double runner = *p0, bench = *bench_actuator.p0;
        const double tolerance = kP0Tolerance * limits.max_increment;
        if (std::abs(runner - bench) > tolerance) {
          throw ConfigError(fmt::format(
              "{}.setup.p0{} = {} m, but {} announces p0 = {} m (p0_mm: {}){}, its zero-force "
              "position{}: {} m apart (more than {} m, a tenth of safety.max_increment), the "
              "test would start with a jump or a loaded specimen. Nothing was sent to the "
              "bench. Set {}.setup.p0{}: {} (the bench's p0_mm / 1000), or correct the "
              "bench's p0_mm",
              where, index, runner, announced.source, bench, bench * 1e3, actuator,
              P0SlipHint(runner, bench), std::abs(runner - bench), tolerance, where, index,
              bench));
        }
      }
      if (bench_actuator.limits) {
        transfer::CheckLimitsAgainstBench(limits, *bench_actuator.limits,
                                          where + ".safety" + index,
                                          announced.source + actuator);
      }
    }
  }
}

void CheckBeforeMoving(const io::RunSpec& spec,
                       const std::vector<std::unique_ptr<substructures::Substructure>>& subs) {
  CheckSchemeStability(spec);
  CheckPhysicalSlotsBeforeMoving(spec, subs);
}

}  // namespace hybridtest::runner
