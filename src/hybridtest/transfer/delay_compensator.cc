// See delay_compensator.h.
#include "hybridtest/transfer/delay_compensator.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

namespace hybridtest::transfer {

void ValidateCompensatorConfig(const CompensatorConfig& c, const std::string& where) {
  auto fail = [&](const std::string& what) { throw ConfigError(where + ": " + what); };
  if (!(c.delay >= 0.0) || !std::isfinite(c.delay)) {
    fail(fmt::format("delay = {}: expected the actuator's delay ≥ 0 in s", c.delay));
  }
  if (c.order < 1 || c.order > 4) fail(fmt::format("order = {}: expected 1..4", c.order));
  if (c.spacing < 0) fail(fmt::format("spacing = {}: expected ≥ 1 tick, or 0 (automatic)", c.spacing));
  if (!(c.window > 0.0)) fail(fmt::format("window = {}: expected > 0 s", c.window));
  if (c.update_every < 1) fail(fmt::format("update_every = {}: expected ≥ 1 tick", c.update_every));
  if (!(c.threshold >= 0.0)) fail("threshold: expected ≥ 0 m");
  for (int i = 0; i < 3; ++i) {
    if (!(c.lower[i] <= c.upper[i])) {
      fail(fmt::format("bounds of a{}: [{}, {}]: expected lower ≤ upper", i, c.lower[i],
                       c.upper[i]));
    }
    if (!(c.rate_limit[i] > 0.0)) fail(fmt::format("rate_limits[{}]: expected > 0", i));
  }
}

DelayCompensator::DelayCompensator(std::unique_ptr<TransferSystem> inner, CompensatorConfig config)
    : inner_(std::move(inner)), config_(config) {
  if (!inner_) throw ConfigError("compensated: the wrapped transfer system is missing");
  ValidateCompensatorConfig(config_, "compensated");
  const auto n = static_cast<std::size_t>(std::max(1, inner_->num_actuators()));
  channels_.reserve(n);
  for (std::size_t k = 0; k < n; ++k) channels_.emplace_back(config_);
  origin_.assign(n, 0.0);
  sent_.assign(n, 0.0);
}

std::string DelayCompensator::Describe() const {
  return fmt::format("{} compensation (τ = {} s) of {}",
                     config_.method == CompensationMethod::kAts ? "ATS" : "polynomial",
                     config_.delay, inner_->Describe());
}

void DelayCompensator::StartPaced(double tick, const Clock& clock) {
  inner_->StartPaced(tick, clock);
  paced_ = true;
  for (ActuatorCompensator& c : channels_) c.Start(tick);
}

double DelayCompensator::compensated_delay() const {
  double smallest = channels_[0].estimated_delay();
  for (const ActuatorCompensator& c : channels_) smallest = std::min(smallest, c.estimated_delay());
  return smallest;
}

void DelayCompensator::Execute(std::span<const double> commands, std::span<Measurement> out) {
  const std::size_t n = channels_.size();
  if (commands.size() != n || out.size() != n) {
    throw TransferError(fmt::format("{}: {} commands for {} actuators", Describe(),
                                    commands.size(), n));
  }
  if (!paced_) {
    std::copy(commands.begin(), commands.end(), origin_.begin());
    inner_->Execute(commands, out);
    return;
  }
  for (std::size_t k = 0; k < n; ++k) {
    sent_[k] = origin_[k] + channels_[k].Compensate(commands[k] - origin_[k]);
  }
  inner_->Execute(sent_, out);
  for (std::size_t k = 0; k < n; ++k) {
    channels_[k].Record(sent_[k] - origin_[k], out[k].position - origin_[k]);
  }
}

nlohmann::json DelayCompensator::ToJson() const {
  if (channels_.size() == 1) return channels_[0].ToJson();
  nlohmann::json actuators = nlohmann::json::array();
  for (const ActuatorCompensator& c : channels_) actuators.push_back(c.ToJson());
  return {{"method", config_.method == CompensationMethod::kAts ? "ats" : "polynomial"},
          {"actuators", std::move(actuators)}};
}

}  // namespace hybridtest::transfer
