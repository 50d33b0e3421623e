// See runge_kutta_scheme.h.
#include "hybridtest/schemes/runge_kutta_scheme.h"

#include <fmt/core.h>

#include "hybridtest/multibody/kane.h"

namespace hybridtest::schemes {

RungeKuttaScheme::RungeKuttaScheme(const multibody::Model& model,
                                   integrators::ButcherTableau tableau, double h, long steps)
    : HybridScheme(model.num_states(), model.num_slots()),
      model_(model),
      data_(model),
      stepper_(std::move(tableau), model.num_states()),
      h_(h),
      steps_(steps),
      x_next_(model.num_states()),
      r_stage_(model.num_slots()),
      d_stage_(model.num_slots()) {}

std::string RungeKuttaScheme::Describe() const {
  return fmt::format("explicit Runge–Kutta '{}' ({}, order {}), h = {} s, {} evaluations per step",
                     stepper_.tableau().name, stepper_.tableau().title, stepper_.tableau().order,
                     h_, stepper_.stages());
}

void RungeKuttaScheme::Step(SubstructureSeam& seam, RowSink& /*rows*/) {
  const long n = point_.step;
  const int n_q = model_.num_coordinates();
  const double t = static_cast<double>(n) * h_;
  has_uncommitted_ = false;
  stepper_.Step(t, h_, point_.x,
                [&](int i, double t_i, const Eigen::VectorXd& x_i, Eigen::Ref<Eigen::VectorXd> k) {
                  if (i == 0) {
                    // x_0 = x_n: its forces were measured when x_n was committed.
                    multibody::CalcStateDerivative<double>(model_, data_, t_i, x_i, point_.r, k);
                    return;
                  }
                  multibody::CalcSlotDisplacements<double>(model_, data_, t_i, x_i.head(n_q),
                                                           d_stage_);
                  seam.Trial({n, i, t_i}, d_stage_, r_stage_);
                  multibody::CalcStateDerivative<double>(model_, data_, t_i, x_i, r_stage_, k);
                },
                x_next_);
  // The new state is tried as stage 0 of the next step; if that trial fails, the runner
  // records x_{n+1} without forces.
  const double t_next = static_cast<double>(n + 1) * h_;
  uncommitted_.step = n + 1;
  uncommitted_.t = t_next;
  uncommitted_.x = x_next_;
  has_uncommitted_ = true;
  multibody::CalcSlotDisplacements<double>(model_, data_, t_next, x_next_.head(n_q), d_stage_);
  seam.Trial({n + 1, 0, t_next}, d_stage_, r_stage_);
  has_uncommitted_ = false;
  point_.step = n + 1;
  point_.t = t_next;
  point_.x.swap(x_next_);
  point_.r = r_stage_;
}

}  // namespace hybridtest::schemes
