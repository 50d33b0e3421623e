#pragma once
// ExplicitRungeKutta: one fixed step of an explicit Runge–Kutta method given by a Butcher
// tableau (odeint's second layer; the loop over steps is the runner's).
//
// For the s-stage tableau (strictly lower triangular a, see butcher_tableau.h)
//
//     c_0   | 0
//     c_1   | a_10    0
//     ⋮     | ⋮             ⋱
//     c_s-1 | a_s-1,0 …  a_s-1,s-2  0
//     ------+---------------------------
//           | b_0     …  b_s-2      b_s-1
//
// one step from (t, x) of size h is the paper's Algorithm 1, with ALL s stages evaluated (the
// printed loop `while i < s` would skip the last one):
//
//     for i = 0 … s-1:
//       t_i = t + c_i h
//       x_i = x + h Σ_{j<i} a_ij k_j
//       k_i = f(t_i, x_i)              ◄── stage(i, t_i, x_i, k_i): the seam where the hybrid
//                                          runner lets the substructures act (trial), then
//                                          evaluates the pure right-hand side
//     x_next = x + h Σ_i b_i k_i
//
// The stepper never rolls back and never changes h: a physical substructure cannot be undone,
// so every step makes exactly stages() trials, in order, and no step is rejected.
//
// All work arrays are allocated by the constructor; Step does no heap allocation.
#include <limits>

#include <Eigen/Core>

#include "hybridtest/integrators/butcher_tableau.h"

namespace hybridtest::integrators {

class ExplicitRungeKutta {
 public:
  // Validates `tableau` (ValidateTableau with where = the tableau's name; throws ConfigError)
  // and preallocates the work arrays for states of `state_size` entries (n). Throws
  // ConfigError when state_size < 1.
  ExplicitRungeKutta(ButcherTableau tableau, int state_size);

  // Number of right-hand-side evaluations per step (s): how many substructure trials one step
  // needs.
  int stages() const { return tableau_.stages(); }

  // Size n of the state vectors Step accepts.
  int state_size() const { return static_cast<int>(x_i_.size()); }

  // The (validated) tableau this stepper uses.
  const ButcherTableau& tableau() const { return tableau_; }

  // One step of size h from state x at time t, into x_next.
  //   t       start time of the step. Unit: [s]
  //   h       step size (any finite value; the runner decides). Unit: [s]
  //   x       (n) state at t
  //   stage   called as stage(int i, double t_i, const Eigen::VectorXd& x_i,
  //           Eigen::Ref<Eigen::VectorXd> k_i) exactly once for every i = 0 … s-1, in order;
  //           it must write all n entries of k_i = f(t_i, x_i) (they are NaN on entry, so a
  //           forgotten entry poisons the step visibly). x_i is only valid during the call.
  //   x_next  (n) state at t + h. It is resized to n if it has another size (which allocates;
  //           pass a preallocated vector in the loop).
  // x_next may alias x (Step(t, h, x, stage, x) updates in place): x is read only before
  // x_next is written. If stage throws, the exception propagates and x_next is untouched.
  // Throws hybridtest::Error if x does not have n entries.
  template <class StageFn>
  void Step(double t, double h, const Eigen::VectorXd& x, StageFn&& stage,
            Eigen::VectorXd& x_next);

  // (n × s) stage derivatives k_0 … k_s-1 of the last step, one per column (NaN before the
  // first step). After a step that threw, columns from the failing stage on are not valid.
  const Eigen::MatrixXd& stage_derivatives() const { return k_; }

 private:
  // Throws hybridtest::Error naming the expected and given sizes.
  [[noreturn]] void ThrowSizeMismatch(Eigen::Index given) const;

  ButcherTableau tableau_;
  Eigen::MatrixXd k_;    // (n × s) stage derivatives
  Eigen::VectorXd x_i_;  // (n) state of the current stage
};

template <class StageFn>
void ExplicitRungeKutta::Step(double t, double h, const Eigen::VectorXd& x, StageFn&& stage,
                              Eigen::VectorXd& x_next) {
  if (x.size() != x_i_.size()) ThrowSizeMismatch(x.size());
  const Eigen::Index s = k_.cols();

  for (Eigen::Index i = 0; i < s; ++i) {
    // Stage state x_i = x + h Σ_{j<i} a_ij k_j, coefficient-wise (no temporaries).
    x_i_ = x;
    for (Eigen::Index j = 0; j < i; ++j) {
      const double a_ij = tableau_.a(i, j);
      if (a_ij != 0.0) x_i_ += (h * a_ij) * k_.col(j);
    }
    // Stage derivative k_i = f(t_i, x_i), computed by the caller.
    k_.col(i).setConstant(std::numeric_limits<double>::quiet_NaN());
    const double t_i = t + tableau_.c(i) * h;
    stage(static_cast<int>(i), t_i, static_cast<const Eigen::VectorXd&>(x_i_),
          Eigen::Ref<Eigen::VectorXd>(k_.col(i)));
  }

  // Update x_next = x + h Σ b_i k_i; x is not read after x_next is first written.
  if (x_next.size() != x.size()) x_next.resize(x.size());
  if (&x_next != &x) x_next = x;
  for (Eigen::Index i = 0; i < s; ++i) {
    const double b_i = tableau_.b(i);
    if (b_i != 0.0) x_next += (h * b_i) * k_.col(i);
  }
}

}  // namespace hybridtest::integrators
