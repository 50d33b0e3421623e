// See hybrid_scheme.h.
#include "hybridtest/schemes/hybrid_scheme.h"

#include <fmt/core.h>

#include <cmath>

#include "hybridtest/common/error.h"

namespace hybridtest::schemes {

HybridScheme::HybridScheme(int state_size, int num_slots) {
  point_.x = Eigen::VectorXd::Zero(state_size);
  point_.r = Eigen::VectorXd::Zero(num_slots);
}

void HybridScheme::Start(double t0, const Eigen::VectorXd& x0, const Eigen::VectorXd& r0) {
  if (x0.size() != point_.x.size() || r0.size() != point_.r.size()) {
    throw Error(fmt::format("{}: Start() with {} states and {} forces; expected {} and {}", name(),
                            x0.size(), r0.size(), point_.x.size(), point_.r.size()));
  }
  point_ = {0, t0, x0, r0};
  has_uncommitted_ = false;
  OnStart();
}

long HybridScheme::EstimatedStepsLeft(double t_end) const {
  const double h = next_step_size();
  if (!(h > 0.0)) return 0;
  return static_cast<long>(std::ceil(std::max(0.0, t_end - point_.t) / h - 1e-9));
}

nlohmann::json ToJson(const Eigen::VectorXd& v) {
  nlohmann::json a = nlohmann::json::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) a.push_back(v(i));
  return a;
}

Eigen::VectorXd VectorFromJson(const nlohmann::json& j, Eigen::Index expected_size,
                               const char* what) {
  if (!j.is_array() || static_cast<Eigen::Index>(j.size()) != expected_size) {
    throw Error(fmt::format("run state: {} has {} entries; this run needs {}", what,
                            j.is_array() ? j.size() : 0, expected_size));
  }
  Eigen::VectorXd v(expected_size);
  for (Eigen::Index i = 0; i < expected_size; ++i) {
    // NaN and infinities are stored as null by nlohmann::json.
    v(i) = j[static_cast<std::size_t>(i)].is_null() ? std::nan("")
                                                      : j[static_cast<std::size_t>(i)].get<double>();
  }
  return v;
}

nlohmann::json HybridScheme::SaveState() const {
  return {{"scheme", name()},
          {"step", point_.step},
          {"t", point_.t},
          {"x", ToJson(point_.x)},
          {"r", ToJson(point_.r)},
          {"own", SaveOwnState()}};
}

void HybridScheme::RestoreState(const nlohmann::json& state) {
  if (!state.is_object() || state.value("scheme", std::string()) != name()) {
    throw Error(fmt::format("run state: it was written by scheme '{}', this run uses '{}'",
                            state.is_object() ? state.value("scheme", std::string("?")) : "?",
                            name()));
  }
  point_.step = state.at("step").get<long>();
  point_.t = state.at("t").get<double>();
  point_.x = VectorFromJson(state.at("x"), point_.x.size(), "x");
  point_.r = VectorFromJson(state.at("r"), point_.r.size(), "r");
  has_uncommitted_ = false;
  RestoreOwnState(state.at("own"));
}

}  // namespace hybridtest::schemes
