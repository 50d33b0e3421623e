// See mr_os.h.
#include "hybridtest/schemes/mr_os.h"

#include <fmt/core.h>

#include <cmath>

#include "hybridtest/common/error.h"
#include "hybridtest/integrators/catalogue.h"
#include "hybridtest/multibody/kane.h"
#include "hybridtest/schemes/step_control.h"

namespace hybridtest::schemes {

MrOs::MrOs(const multibody::Model& model, const SchemeConfig& config, const SlotInfo& slots,
           double dt, double duration, long steps)
    : OperatorSplittingScheme(model, config, slots, dt, duration, steps,
                              kMrOsStabilityConstant),
      rk4_(integrators::FindTableau("rk4"), model.num_states()) {
  for (Eigen::VectorXd* v : {&rho_prev_, &rho_cur_, &rho_new_, &d_, &rho_, &r_, &r_sample_}) {
    v->setZero(m_);
  }
  for (Eigen::VectorXd* v : {&x_pred_, &x_corr_, &x_sub_}) v->setZero(model.num_states());
}

std::string MrOs::Describe() const {
  return fmt::format("MR-OS (multi-rate operator splitting), RK4 substeps ≤ {} s, macro {}",
                     config_.substep, StepDescription());
}

void MrOs::OnStart() {
  multibody::CalcSlotDisplacements<double>(model_, data_, point_.t, point_.x.head(n_), d_last_);
  if (coupled()) {
    rho_cur_ = point_.r - slots_.k0_matrix * d_last_;
  } else {
    rho_cur_ = point_.r - slots_.k0.cwiseProduct(d_last_);
  }
  t_cur_ = point_.t;
  samples_ = 1;
}

void MrOs::Residual(double t, bool with_new, Eigen::VectorXd& rho) const {
  if (!with_new) {
    // Predictor: linear extrapolation through the last two samples (constant with one).
    if (samples_ < 2) {
      rho = rho_cur_;
      return;
    }
    const double w = (t - t_cur_) / (t_cur_ - t_prev_);
    rho = rho_cur_ + w * (rho_cur_ - rho_prev_);
    return;
  }
  // Corrector: Lagrange through (T_{k−1}), T_k, T_{k+1}.
  if (samples_ < 2) {
    const double w = (t - t_cur_) / (t_new_ - t_cur_);
    rho = rho_cur_ + w * (rho_new_ - rho_cur_);
    return;
  }
  const double l0 = (t - t_cur_) * (t - t_new_) / ((t_prev_ - t_cur_) * (t_prev_ - t_new_));
  const double l1 = (t - t_prev_) * (t - t_new_) / ((t_cur_ - t_prev_) * (t_cur_ - t_new_));
  const double l2 = (t - t_prev_) * (t - t_cur_) / ((t_new_ - t_prev_) * (t_new_ - t_cur_));
  rho = l0 * rho_prev_ + l1 * rho_cur_ + l2 * rho_new_;
}

void MrOs::Integrate(double h, bool with_new, Eigen::VectorXd& x_end,
                     RowSink* rows) {
  const long substeps = std::max(1L, static_cast<long>(std::ceil(h / config_.substep - 1e-9)));
  const double hs = h / static_cast<double>(substeps);
  x_end = point_.x;
  for (long j = 0; j < substeps; ++j) {
    const double t = point_.t + static_cast<double>(j) * hs;
    rk4_.Step(t, hs, x_end,
              [&](int, double t_i, const Eigen::VectorXd& x_i, Eigen::Ref<Eigen::VectorXd> k) {
                multibody::CalcSlotDisplacements<double>(model_, data_, t_i, x_i.head(n_), d_);
                Residual(t_i, with_new, rho_);
                if (coupled()) {
                  r_.noalias() = slots_.k0_matrix * d_;
                  r_ += rho_;
                } else {
                  r_ = slots_.k0.cwiseProduct(d_) + rho_;
                }
                multibody::CalcStateDerivative<double>(model_, data_, t_i, x_i, r_, k);
              },
              x_end);
    if (rows != nullptr && j + 1 < substeps) {
      const double t_row = point_.t + static_cast<double>(j + 1) * hs;
      multibody::CalcSlotDisplacements<double>(model_, data_, t_row, x_end.head(n_), d_);
      Residual(t_row, with_new, rho_);
      if (coupled()) {
        r_.noalias() = slots_.k0_matrix * d_;
        r_ += rho_;
      } else {
        r_ = slots_.k0.cwiseProduct(d_) + rho_;
      }
      rows->Row(t_row, x_end, r_);
    }
  }
}

void MrOs::Step(SubstructureSeam& seam, RowSink& rows) {
  const long k = point_.step;
  double h = StepToTake();
  double t_next = 0.0;
  // Predict (shortening the macro step, before anything moves, while the command would use
  // too much of a slot's increment limit).
  for (int attempt = 0;; ++attempt) {
    t_next = StepEnd(h);
    Integrate(h, false, x_pred_, nullptr);
    multibody::CalcSlotDisplacements<double>(model_, data_, t_next, x_pred_.head(n_), d_);
    if (!config_.adaptive.enabled || attempt >= 20 || h <= config_.adaptive.dt_min ||
        IncrementRatio(d_, d_last_, slots_.max_increment) <= kIncrementMargin) {
      break;
    }
    h = std::max(config_.adaptive.dt_min, 0.5 * h);
  }
  const Eigen::VectorXd& d_imposed = d_;
  // Evaluate: the one specimen evaluation of the macro step.
  seam.Trial({k + 1, 0, t_next}, d_imposed, r_sample_);
  t_new_ = t_next;
  if (coupled()) {
    rho_new_ = r_sample_;
    rho_new_.noalias() -= slots_.k0_matrix * d_imposed;
  } else {
    rho_new_ = r_sample_ - slots_.k0.cwiseProduct(d_imposed);
  }
  d_last_ = d_imposed;
  // Correct, journalling the substeps.
  Integrate(h, true, x_corr_, &rows);
  multibody::CalcSlotDisplacements<double>(model_, data_, t_next, x_corr_.head(n_), d_);
  // Commit and shift the samples.
  if (coupled()) {
    point_.r.noalias() = slots_.k0_matrix * d_;
    point_.r += rho_new_;
  } else {
    point_.r = slots_.k0.cwiseProduct(d_) + rho_new_;
  }
  point_.x = x_corr_;
  point_.t = t_next;
  point_.step = k + 1;
  t_prev_ = t_cur_;
  rho_prev_ = rho_cur_;
  t_cur_ = t_new_;
  rho_cur_ = rho_new_;
  samples_ = 2;
  // Control: the next macro step from the imposed − corrected difference, within the
  // stability guard's bound.
  if (config_.adaptive.enabled) {
    const double e = (d_ - d_last_).lpNorm<Eigen::Infinity>();
    ChooseNextStep(h, NextStepSize(config_.adaptive, h, e, 3.0), e, d_last_, r_sample_);
  }
}

nlohmann::json MrOs::SaveOwnState() const {
  nlohmann::json state = {{"samples", samples_},
                          {"t_prev", t_prev_},
                          {"t_cur", t_cur_},
                          {"rho_prev", ToJson(rho_prev_)},
                          {"rho_cur", ToJson(rho_cur_)}};
  SaveSplittingState(state);
  return state;
}

void MrOs::RestoreOwnState(const nlohmann::json& state) {
  RestoreSplittingState(state);
  samples_ = state.at("samples").get<int>();
  t_prev_ = state.at("t_prev").get<double>();
  t_cur_ = state.at("t_cur").get<double>();
  rho_prev_ = VectorFromJson(state.at("rho_prev"), m_, "mr-os rho_prev");
  rho_cur_ = VectorFromJson(state.at("rho_cur"), m_, "mr-os rho_cur");
}

}  // namespace hybridtest::schemes
