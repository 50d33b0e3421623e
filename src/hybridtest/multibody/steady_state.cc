// A steady state by Gauss–Newton on the speed rates. See steady_state.h.
#include "hybridtest/multibody/steady_state.h"

#include <fmt/core.h>

#include <Eigen/LU>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>

#include "hybridtest/common/error.h"
#include "hybridtest/multibody/kane.h"

namespace hybridtest::multibody {

namespace {

// The restoring forces r = k d(q) (num_slots) on T (double or AutoDiff).
template <typename T>
VectorX<T> ClosedSlots(const Model& model, Data<T>& data, const T& t, const VectorX<T>& x,
                       const std::vector<double>& slot_stiffness) {
  VectorX<T> r(model.num_slots());
  for (int s = 0; s < model.num_slots(); ++s) r(s) = t * 0.0;
  if (slot_stiffness.empty() || model.num_slots() == 0) return r;
  CalcSlotDisplacements<T>(model, data, t, x.head(model.num_coordinates()), r);
  for (int s = 0; s < model.num_slots(); ++s) r(s) *= slot_stiffness[static_cast<std::size_t>(s)];
  return r;
}

// The equations R(x) = 0 and their Jacobian in the free coordinates.
//   Nothing driven: R = u̇ (all n rows); G = (J T)[u rows, free columns] (LinearizeConstrained).
//   Speeds d driven (unconstrained models): the drive holds u̇_d = 0 with whatever generalized
//   force it takes, so the other speeds f obey M_ff u̇_f = g_f: R = M_ff⁻¹ g_f (still speed
//   rates), G = M_ff⁻¹ ∂g_f/∂q_free (exact, AutoDiff; the term ∂M_ff⁻¹/∂q g_f is left out: it
//   vanishes at R = 0, so Newton stays quadratic).
class SteadyEquations {
 public:
  SteadyEquations(const Model& model, double t, const std::vector<int>& free,
                  const std::vector<double>& slot_stiffness, const std::vector<int>& driven)
      : model_(model), t_(t), free_(free), k_(slot_stiffness), driven_(!driven.empty()),
        data_(model) {
    for (int k = 0; k < model.num_coordinates(); ++k)
      if (std::find(driven.begin(), driven.end(), k) == driven.end()) rows_.push_back(k);
  }
  const std::vector<int>& rows() const { return rows_; }
  int size() const { return static_cast<int>(rows_.size()); }

  Eigen::VectorXd Residual(const Eigen::VectorXd& x) {
    const int n = model_.num_coordinates();
    const Eigen::VectorXd r = ClosedSlots<double>(model_, data_, t_, x, k_);
    Eigen::VectorXd out(size());
    if (!driven_) {
      Eigen::VectorXd xdot(model_.num_states());
      CalcStateDerivative<double>(model_, data_, t_, x, r, xdot);
      for (int i = 0; i < size(); ++i) out(i) = xdot(n + rows_[static_cast<std::size_t>(i)]);
      return out;
    }
    CalcKinematics<double>(model_, data_, t_, x);
    CalcMassMatrix<double>(model_, data_);
    CalcForcing<double>(model_, data_, r);
    for (int i = 0; i < size(); ++i) out(i) = data_.g(rows_[static_cast<std::size_t>(i)]);
    return Mff().solve(out);
  }

  Eigen::MatrixXd Jacobian(const Eigen::VectorXd& x) {
    const int n = model_.num_coordinates(), nf = static_cast<int>(free_.size());
    Eigen::MatrixXd G(size(), nf);
    if (!driven_) {
      const Linearization lin = LinearizeConstrained(model_, t_, x, k_);
      for (int j = 0; j < nf; ++j) {
        const int k = free_[static_cast<std::size_t>(j)];
        const auto at = std::find(lin.states.begin(), lin.states.end(), k);
        if (at == lin.states.end()) {
          throw ModelError(fmt::format(
              "coordinate {} is dependent (solved from the constraints when the state is "
              "assembled), so it cannot be solved for u̇ = 0; name an independent coordinate "
              "instead", model_.coordinates()[k].name));
        }
        const Eigen::VectorXd dx = lin.T.col(at - lin.states.begin());
        for (int i = 0; i < size(); ++i) {
          G(i, j) = lin.J.row(n + rows_[static_cast<std::size_t>(i)]).dot(dx);
        }
      }
      return G;
    }
    // ∂g_f/∂q_free by AutoDiff, in chunks of kMaxDerivatives free coordinates.
    Data<AutoDiff> ad(model_);
    VectorX<AutoDiff> xa(model_.num_states());
    for (int first = 0; first < nf; first += kMaxDerivatives) {
      const int c = std::min(kMaxDerivatives, nf - first);
      for (int i = 0; i < xa.size(); ++i) xa(i) = AutoDiff(x(i), Derivatives::Zero(c));
      for (int j = 0; j < c; ++j) {
        xa(free_[static_cast<std::size_t>(first + j)]).derivatives()(j) = 1.0;
      }
      const AutoDiff ta(t_, Derivatives::Zero(c));
      VectorX<AutoDiff> r = ClosedSlots<AutoDiff>(model_, ad, ta, xa, k_);
      for (int s = 0; s < r.size(); ++s)
        if (r(s).derivatives().size() != c) r(s).derivatives() = Derivatives::Zero(c);
      CalcKinematics<AutoDiff>(model_, ad, ta, xa);
      CalcForcing<AutoDiff>(model_, ad, r);
      for (int i = 0; i < size(); ++i) {
        const Derivatives& d = ad.g(rows_[static_cast<std::size_t>(i)]).derivatives();
        for (int j = 0; j < c; ++j) G(i, first + j) = j < d.size() ? d(j) : 0.0;
      }
    }
    Residual(x);  // M at x
    return Mff().solve(G);
  }

 private:
  Eigen::PartialPivLU<Eigen::MatrixXd> Mff() const {
    Eigen::MatrixXd m(size(), size());
    for (int i = 0; i < size(); ++i)
      for (int j = 0; j < size(); ++j)
        m(i, j) = data_.M(rows_[static_cast<std::size_t>(i)], rows_[static_cast<std::size_t>(j)]);
    return Eigen::PartialPivLU<Eigen::MatrixXd>(m);
  }

  const Model& model_;
  double t_;
  const std::vector<int>& free_;
  const std::vector<double>& k_;
  bool driven_;
  std::vector<int> rows_;
  Data<double> data_;
};

std::string FreeNames(const Model& model, const std::vector<int>& free) {
  std::string out;
  for (int k : free) out += (out.empty() ? "" : ", ") + model.coordinates()[k].name;
  return out;
}

// The state with the free coordinates moved by `step`, assembled; false if the constraints
// cannot be met there or the equations cannot be evaluated (a singular M).
bool Trial(const Model& model, SteadyEquations& equations, double t, const Eigen::VectorXd& x,
           const std::vector<int>& free, const Eigen::VectorXd& step, Eigen::VectorXd& x_out,
           Eigen::VectorXd& rates_out) {
  Eigen::VectorXd trial = x;
  for (std::size_t j = 0; j < free.size(); ++j) {
    trial(free[j]) += step(static_cast<Eigen::Index>(j));
  }
  try {
    x_out = AssembleState(model, t, trial).x;
    rates_out = equations.Residual(x_out);
  } catch (const ModelError&) {
    return false;
  }
  return rates_out.allFinite();
}

// Refuses an empty or repeated list of free coordinates, indices out of range and drives the
// equations cannot take.
void CheckArguments(const Model& model, const std::vector<int>& free_coordinates,
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
  for (int k : options.driven_speeds) {
    if (k < 0 || k >= n) {
      throw ModelError(fmt::format("speed index {} is out of range (n = {})", k, n));
    }
  }
  if (!options.driven_speeds.empty() && model.has_constraints()) {
    throw ModelError("driven speeds are supported for unconstrained models only (a drive on a "
                     "constrained model would need its force through the constraints); leave "
                     "the driven speeds out");
  }
  if (static_cast<int>(options.driven_speeds.size()) >= n) {
    throw ModelError("every speed is driven, so no speed rate is left to vanish: leave some "
                     "speeds undriven");
  }
}

}  // namespace

SpeedRateResidual CalcSpeedRateResidual(const Model& model, double t, const Eigen::VectorXd& x,
                                        const std::vector<double>& slot_stiffness) {
  SpeedRateResidual out;
  if (model.num_coordinates() == 0) return out;
  SteadyEquations equations(model, t, {}, slot_stiffness, {});
  const Eigen::VectorXd rates = equations.Residual(AssembleState(model, t, x).x);
  Eigen::Index k = 0;
  out.residual = rates.cwiseAbs().maxCoeff(&k);
  out.worst_speed = static_cast<int>(k);
  return out;
}

std::string SpeedRateUnit(const Model& model, int k) {
  const std::string& unit = model.speeds()[static_cast<std::size_t>(k)].unit;
  if (unit.size() > 2 && unit.compare(unit.size() - 2, 2, "/s") == 0) return unit + "²";
  return unit.empty() ? "1/s" : unit + "/s";
}

SteadyState FindSteadyState(const Model& model, double t, const Eigen::VectorXd& x,
                            const std::vector<int>& free_coordinates,
                            const std::vector<double>& slot_stiffness,
                            const SteadyStateOptions& options) {
  CheckArguments(model, free_coordinates, options);
  SteadyState out;
  out.free_coordinates = free_coordinates;
  out.driven_speeds = options.driven_speeds;
  out.x = AssembleState(model, t, x).x;
  SteadyEquations equations(model, t, free_coordinates, slot_stiffness, options.driven_speeds);
  const std::vector<int>& rows = equations.rows();
  Eigen::VectorXd rates = equations.Residual(out.x);
  const int nf = static_cast<int>(free_coordinates.size());
  const std::string names = FreeNames(model, free_coordinates);
  std::string why;
  const auto worst = [&] {
    Eigen::Index i = 0;
    out.residual = rates.cwiseAbs().maxCoeff(&i);
    out.worst_speed = rows[static_cast<std::size_t>(i)];
  };
  for (;; ++out.iterations) {
    worst();
    if (out.residual <= options.tolerance) {
      out.converged = true;
      return out;
    }
    if (out.iterations >= options.max_iterations) {
      why = fmt::format("the iteration limit ({}) was reached", options.max_iterations);
      break;
    }
    // G = ∂R/∂q_free (along the constraint manifold), exact.
    const Eigen::MatrixXd G = equations.Jacobian(out.x);
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
      if (Trial(model, equations, t, out.x, free_coordinates, a * step, x_next, rates_next) &&
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
  worst();
  out.message = fmt::format(
      "no steady state found for {} after {} iteration(s): {}; the speed rates' residual is "
      "max |u̇| = {:.3g} {} (u̇ of speed '{}'), above the tolerance {:.3g}. Try another start "
      "(--at q=..., or at= from Python), solve for more or fewer coordinates, hold other "
      "speeds, or name the speeds a drive holds (--driven)",
      names, out.iterations, why, out.residual, SpeedRateUnit(model, out.worst_speed),
      model.speeds()[static_cast<std::size_t>(out.worst_speed)].name, options.tolerance);
  return out;
}

}  // namespace hybridtest::multibody
