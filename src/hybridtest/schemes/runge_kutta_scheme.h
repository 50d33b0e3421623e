#pragma once
// RungeKuttaScheme: the paper's Algorithm 1 (all s stages) as a hybrid scheme, with any
// explicit Butcher tableau (integrators/explicit_runge_kutta.h shows the formulas) and a fixed
// step h. Every stage is a specimen evaluation: s trials per step.
//
//   step n → n+1 (t_n = n h):
//     stage 0: k_0 = f(t_n, x_n, r_n) with r_n measured at x_n (the trial that committed x_n)
//     stage i = 1..s−1: x_i = x_n + h Σ_j a_ij k_j, r_i = seam.Trial(d(t_i, x_i)),
//                       k_i = f(t_i, x_i, r_i)
//     x_{n+1} = x_n + h Σ b_i k_i
//     r_{n+1} = seam.Trial(d(t_{n+1}, x_{n+1}))  (stage 0 of step n+1; the session commits
//                                               and journals it)
//
// Every stage is a trial, in the paper's order. Explicit RK is only conditionally stable: h must lie within the tableau's stability region for the model's
// fastest eigenvalue (the rotor's generator damping gives −958 1/s: Heun needs h ≤ 2.09 ms).
#include "hybridtest/integrators/explicit_runge_kutta.h"
#include "hybridtest/multibody/data.h"
#include "hybridtest/multibody/model.h"
#include "hybridtest/schemes/hybrid_scheme.h"

namespace hybridtest::schemes {

class RungeKuttaScheme final : public HybridScheme {
 public:
  // h [s] > 0; `steps` steps of h make the run (t_end = t0 + steps h). Throws ConfigError on an
  // invalid tableau.
  RungeKuttaScheme(const multibody::Model& model, integrators::ButcherTableau tableau, double h,
                   long steps);

  std::string name() const override { return stepper_.tableau().name; }
  std::string Describe() const override;
  int evaluations_per_step() const override { return stepper_.stages(); }
  void Step(SubstructureSeam& seam, RowSink& rows) override;
  bool finished() const override { return point_.step >= steps_; }
  double next_step_size() const override { return h_; }

 private:
  const multibody::Model& model_;
  multibody::Data<double> data_;
  integrators::ExplicitRungeKutta stepper_;
  double h_;
  long steps_;
  Eigen::VectorXd x_next_;  // (2n)
  Eigen::VectorXd r_stage_; // (m)
  Eigen::VectorXd d_stage_; // (m) slot displacements of the stage's trial
};

}  // namespace hybridtest::schemes
