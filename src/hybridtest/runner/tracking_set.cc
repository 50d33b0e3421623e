// See tracking_set.h.
#include "hybridtest/runner/tracking_set.h"

#include <cmath>
#include <limits>

namespace hybridtest::runner {

void TrackingSet::Reserve(std::vector<Block> blocks, long capacity, double tick, long window) {
  blocks_ = std::move(blocks);
  std::size_t actuators = 0, slots = 0;
  Eigen::Index widest = 0, tallest = 0;
  for (const Block& b : blocks_) {
    actuators += static_cast<std::size_t>(b.num_actuators);
    slots += b.slots.size();
    widest = std::max<Eigen::Index>(widest, b.num_actuators);
    tallest = std::max<Eigen::Index>(tallest, static_cast<Eigen::Index>(b.slots.size()));
  }
  actuators_.assign(actuators, {});
  slots_.assign(slots, {});
  for (auto& c : actuators_) c.Reserve(capacity, tick);
  for (auto& c : slots_) c.Reserve(capacity, tick);
  live_.assign(actuators + slots, std::numeric_limits<double>::quiet_NaN());
  window_ = window;
  next_ = 0;
  a_c_.resize(widest);
  a_m_.resize(widest);
  d_c_.resize(tallest);
  d_m_.resize(tallest);
}

void TrackingSet::Add(std::span<const substructures::Exchange> exchanges) {
  std::size_t a = 0, s = 0;
  for (const Block& b : blocks_) {
    const Eigen::Index n = b.num_actuators;
    const auto m = static_cast<Eigen::Index>(b.slots.size());
    for (Eigen::Index k = 0; k < n; ++k) {
      const auto e = static_cast<std::size_t>(b.first_actuator + k);
      if (e >= exchanges.size()) return;
      actuators_[a++].Add(exchanges[e].command, exchanges[e].position);
      a_c_(k) = exchanges[e].command - b.p0(k);
      a_m_(k) = exchanges[e].position - b.p0(k);
    }
    d_c_.head(m).noalias() = b.slot_of_actuator * a_c_.head(n);
    d_m_.head(m).noalias() = b.slot_of_actuator * a_m_.head(n);
    for (Eigen::Index i = 0; i < m; ++i) slots_[s++].Add(d_c_(i), d_m_(i));
  }
}

void TrackingSet::UpdateLiveJ1() {
  if (live_.empty()) return;
  const std::size_t k = next_;
  next_ = (next_ + 1) % live_.size();
  live_[k] = k < actuators_.size() ? actuators_[k].J1_ms(window_)
                                   : slots_[k - actuators_.size()].J1_ms(window_);
}

nlohmann::json TrackingSet::ToJson() const {
  nlohmann::json actuators = nlohmann::json::array(), slots = nlohmann::json::array();
  std::size_t a = 0, s = 0;
  for (const Block& b : blocks_) {
    for (int k = 0; k < b.num_actuators; ++k) {
      nlohmann::json j = {{"substructure", b.name}, {"actuator", k + 1}};
      j.update(actuators_[a++].ToJson());
      actuators.push_back(std::move(j));
    }
    for (const std::string& name : b.slots) {
      nlohmann::json j = {{"slot", name}, {"substructure", b.name}};
      j.update(slots_[s++].ToJson());
      slots.push_back(std::move(j));
    }
  }
  return {{"actuators", std::move(actuators)}, {"slots", std::move(slots)}};
}

}  // namespace hybridtest::runner
