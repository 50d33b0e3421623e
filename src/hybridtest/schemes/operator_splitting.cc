// See operator_splitting.h.
#include "hybridtest/schemes/operator_splitting.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "hybridtest/common/error.h"
#include "hybridtest/schemes/step_control.h"

namespace hybridtest::schemes {

OperatorSplittingScheme::OperatorSplittingScheme(const multibody::Model& model,
                                                 const SchemeConfig& config, const SlotInfo& slots,
                                                 double dt, double duration, long steps,
                                                 double stability_constant)
    : HybridScheme(model.num_states(), model.num_slots()),
      model_(model),
      config_(config),
      slots_(slots),
      h_(config.adaptive.enabled ? std::clamp(dt, config.adaptive.dt_min, config.adaptive.dt_max)
                                 : dt),
      duration_(duration),
      steps_(steps),
      n_(model.num_coordinates()),
      m_(model.num_slots()),
      data_(model),
      d_last_(Eigen::VectorXd::Zero(model.num_slots())),
      guard_(model.num_coordinates(), model.num_slots(), stability_constant) {
  if (coupled() && (slots_.k0_matrix.rows() != m_ || slots_.k0_matrix.cols() != m_ ||
                    !slots_.k0_matrix.allFinite())) {
    throw ConfigError(fmt::format("integrator.scheme = {}: the coupled K0 is {} × {} or not "
                                  "finite; expected {} × {}: give every substructure of several "
                                  "slots its initial_stiffness (a matrix in N/m) or `measure`",
                                  SchemeKindName(config.kind), slots_.k0_matrix.rows(),
                                  slots_.k0_matrix.cols(), m_, m_));
  }
  for (int s = 0; s < m_; ++s) {
    if (!std::isfinite(slots_.k0(s))) {
      const std::string& slot = model.slots()[s].info.name;
      throw ConfigError(fmt::format("integrator.scheme = {}: slot {} has no initial stiffness K0; "
                                    "give substructures.{}.initial_stiffness (N/m) or `measure`",
                                    SchemeKindName(config.kind), slot, slot));
    }
  }
}

bool OperatorSplittingScheme::finished() const {
  if (!config_.adaptive.enabled) return point_.step >= steps_;
  return point_.t >= duration_ * (1.0 - 1e-12);
}

std::string OperatorSplittingScheme::StepDescription() const {
  return config_.adaptive.enabled
             ? fmt::format("adaptive step {}–{} s, tolerance {} m", config_.adaptive.dt_min,
                           config_.adaptive.dt_max, config_.adaptive.tolerance)
             : fmt::format("fixed step {} s", h_);
}

double OperatorSplittingScheme::StepToTake() const {
  return config_.adaptive.enabled ? StepTowards(point_.t, duration_, h_, config_.adaptive.dt_min)
                                  : h_;
}

double OperatorSplittingScheme::StepEnd(double h) const {
  return config_.adaptive.enabled ? point_.t + h : static_cast<double>(point_.step + 1) * h_;
}

void OperatorSplittingScheme::ChooseNextStep(double h, double h_next, double e,
                                             const Eigen::VectorXd& d, const Eigen::VectorXd& r) {
  guard_.AddSample(d, r);
  guard_.AddErrorEstimate(e, h, config_.adaptive.tolerance);
  // The modes (an eigenproblem of size 2n) only where a bound can arise.
  if (guard_.HasExcess(slots_.k0)) {
    guard_.UpdateModes(model_, data_, point_.t, point_.x, point_.r, slots_.k0);
  }
  h_ = guard_.Limit(h_next, h, config_.adaptive.dt_min, slots_.k0);
}

void OperatorSplittingScheme::SaveSplittingState(nlohmann::json& state) const {
  state["h"] = h_;
  state["guard"] = guard_.SaveState();
  state["k0"] = ToJson(slots_.k0);
  if (coupled()) {
    state["k0_matrix"] = ToJson(Eigen::VectorXd(
        Eigen::Map<const Eigen::VectorXd>(slots_.k0_matrix.data(), slots_.k0_matrix.size())));
  }
  state["d_last"] = ToJson(d_last_);
}

void OperatorSplittingScheme::RestoreSplittingState(const nlohmann::json& state) {
  h_ = state.at("h").get<double>();
  slots_.k0 = VectorFromJson(state.at("k0"), m_, "k0");
  if (state.contains("k0_matrix")) {
    const Eigen::VectorXd k = VectorFromJson(state.at("k0_matrix"), m_ * m_, "k0_matrix");
    slots_.k0_matrix = Eigen::Map<const Eigen::MatrixXd>(k.data(), m_, m_);
  }
  d_last_ = VectorFromJson(state.at("d_last"), m_, "d_last");
  guard_.RestoreState(state.contains("guard") ? state.at("guard") : nlohmann::json());
}

}  // namespace hybridtest::schemes
