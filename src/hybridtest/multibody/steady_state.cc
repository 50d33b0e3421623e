// A steady state by Gauss–Newton on the speed rates. See steady_state.h.
#include "hybridtest/multibody/steady_state.h"

#include <fmt/core.h>

#include <Eigen/QR>
#include <algorithm>
#include <cmath>

#include "hybridtest/common/error.h"
#include "hybridtest/multibody/kane.h"

namespace hybridtest::multibody {

namespace {

// u̇ (n) at (t, x) with r = k d(q).
Eigen::VectorXd SpeedRates(const Model& model, Data<double>& data, double t,
                           const Eigen::VectorXd& x, const std::vector<double>& slot_stiffness) {
  const int n = model.num_coordinates();
  Eigen::VectorXd r = Eigen::VectorXd::Zero(model.num_slots());
  if (!slot_stiffness.empty() && model.num_slots() > 0) {
    CalcSlotDisplacements<double>(model, data, t, x.head(n), r);
    for (int s = 0; s < model.num_slots(); ++s) r(s) *= slot_stiffness[static_cast<std::size_t>(s)];
  }
  Eigen::VectorXd xdot(model.num_states());
  CalcStateDerivative<double>(model, data, t, x, r, xdot);
  return xdot.segment(n, n);
}

std::string FreeNames(const Model& model, const std::vector<int>& free) {
  std::string out;
  for (int k : free) out += (out.empty() ? "" : ", ") + model.coordinates()[k].name;
  return out;
}

// The state with the free coordinates moved by `step`, assembled; false if the constraints
// cannot be met there or the equations cannot be evaluated (a singular M).
bool Trial(const Model& model, Data<double>& data, double t, const Eigen::VectorXd& x,
           const std::vector<int>& free, const Eigen::VectorXd& step,
           const std::vector<double>& slot_stiffness, Eigen::VectorXd& x_out,
           Eigen::VectorXd& rates_out) {
  Eigen::VectorXd trial = x;
  for (std::size_t j = 0; j < free.size(); ++j) trial(free[j]) += step(static_cast<Eigen::Index>(j));
  try {
    x_out = AssembleState(model, t, trial).x;
    rates_out = SpeedRates(model, data, t, x_out, slot_stiffness);
  } catch (const ModelError&) {
    return false;
  }
  return rates_out.allFinite();
}

}  // namespace

std::string SpeedRateUnit(const Model& model, int k) {
  const std::string& unit = model.speeds()[static_cast<std::size_t>(k)].unit;
  if (unit.size() > 2 && unit.compare(unit.size() - 2, 2, "/s") == 0) return unit + "²";
  return unit.empty() ? "1/s" : unit + "/s";
}

SteadyState FindSteadyState(const Model& model, double t, const Eigen::VectorXd& x,
                            const std::vector<int>& free_coordinates,
                            const std::vector<double>& slot_stiffness,
                            const SteadyStateOptions& options) {
  const int n = model.num_coordinates();
  if (free_coordinates.empty()) {
    throw ModelError("a steady state needs at least one coordinate to solve for");
  }
  for (std::size_t j = 0; j < free_coordinates.size(); ++j) {
    const int k = free_coordinates[j];
    if (k < 0 || k >= n) {
      throw ModelError(fmt::format("coordinate index {} is out of range (n = {})", k, n));
    }
    if (std::count(free_coordinates.begin(), free_coordinates.end(), k) > 1) {
      throw ModelError(fmt::format("coordinate {} is named twice among the coordinates to "
                                   "solve for", model.coordinates()[k].name));
    }
  }
  SteadyState out;
  out.free_coordinates = free_coordinates;
  out.x = AssembleState(model, t, x).x;
  Data<double> data(model);
  Eigen::VectorXd rates = SpeedRates(model, data, t, out.x, slot_stiffness);
  const int nf = static_cast<int>(free_coordinates.size());
  const std::string names = FreeNames(model, free_coordinates);
  std::string why;
  for (;; ++out.iterations) {
    out.residual = rates.cwiseAbs().maxCoeff(&out.worst_speed);
    if (out.residual <= options.tolerance) {
      out.converged = true;
      return out;
    }
    if (out.iterations >= options.max_iterations) {
      why = fmt::format("the iteration limit ({}) was reached", options.max_iterations);
      break;
    }
    // G = ∂u̇/∂q_free along the constraint manifold (J T, exact).
    const Linearization lin = LinearizeConstrained(model, t, out.x, slot_stiffness);
    Eigen::MatrixXd G(n, nf);
    for (int j = 0; j < nf; ++j) {
      const int k = free_coordinates[static_cast<std::size_t>(j)];
      const auto at = std::find(lin.states.begin(), lin.states.end(), k);
      if (at == lin.states.end()) {
        throw ModelError(fmt::format(
            "coordinate {} is dependent (solved from the constraints when the state is "
            "assembled), so it cannot be solved for u̇ = 0; name an independent coordinate "
            "instead", model.coordinates()[k].name));
      }
      G.col(j) = lin.J.middleRows(n, n) * lin.T.col(at - lin.states.begin());
    }
    const double scale = std::max(1.0, G.cwiseAbs().maxCoeff());
    for (int j = 0; j < nf; ++j) {
      if (G.col(j).cwiseAbs().maxCoeff() <= 1e-13 * scale) {
        why = fmt::format("no speed rate depends on coordinate {} here (nothing restores it: "
                          "no spring, gravity or constraint moves u̇ when it moves), so it "
                          "cannot be solved for; hold it (leave it out of the coordinates to "
                          "solve for) or add the force that sets it",
                          model.coordinates()[free_coordinates[static_cast<std::size_t>(j)]].name);
        break;
      }
    }
    if (!why.empty()) break;
    // The Gauss–Newton step, damped by backtracking on |u̇|₂².
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(G);
    qr.setThreshold(1e-12);
    const Eigen::VectorXd step = qr.solve(-rates);
    const double phi0 = rates.squaredNorm();
    const double decrease = (G * step).squaredNorm();
    bool accepted = false;
    Eigen::VectorXd x_next, rates_next;
    for (double a = 1.0; a >= 0x1p-20 && step.allFinite(); a *= 0.5) {
      if (Trial(model, data, t, out.x, free_coordinates, a * step, slot_stiffness, x_next,
                rates_next) &&
          rates_next.squaredNorm() <= phi0 - 2e-4 * a * decrease &&
          rates_next.squaredNorm() < phi0) {
        accepted = true;
        break;
      }
    }
    if (!accepted) {
      why = "no step along the least-squares direction reduces |u̇| (it has a minimum here "
            "that is not zero: there is no steady state near this start)";
      break;
    }
    out.x = std::move(x_next);
    rates = std::move(rates_next);
  }
  out.residual = rates.cwiseAbs().maxCoeff(&out.worst_speed);
  out.message = fmt::format(
      "no steady state found for {} after {} iteration(s): {}; the speed rates' residual is "
      "max |u̇| = {:.3g} {} (u̇ of speed '{}'), above the tolerance {:.3g}. Try another start "
      "(--at q=..., or at= from Python), solve for more or fewer coordinates, or hold other "
      "speeds",
      names, out.iterations, why, out.residual, SpeedRateUnit(model, out.worst_speed),
      model.speeds()[static_cast<std::size_t>(out.worst_speed)].name, options.tolerance);
  return out;
}

}  // namespace hybridtest::multibody
