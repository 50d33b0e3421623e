// See real_time_panel.h.
#include "hybridtest/monitor/real_time_panel.h"

#include <algorithm>
#include <cmath>

namespace hybridtest::monitor {
namespace {

constexpr double kSmallest = 1e-7;  // [s] the upper edge of bin 0
constexpr double kRatio = 1.05;     // the bins' width, as a ratio of their edges

nlohmann::json Number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }

}  // namespace

void DurationHistogram::Add(double seconds) {
  if (!std::isfinite(seconds)) return;
  int bin = 0;
  if (seconds >= kSmallest) {
    bin = 1 + static_cast<int>(std::floor(std::log(seconds / kSmallest) / std::log(kRatio)));
  }
  ++bins_[static_cast<std::size_t>(std::clamp(bin, 0, kBins - 1))];
  ++count_;
  max_ = count_ == 1 ? seconds : std::max(max_, seconds);
}

double DurationHistogram::Percentile(double p) const {
  if (count_ == 0) return 0.0;
  const auto wanted = std::max<long>(1, static_cast<long>(std::ceil(p * static_cast<double>(count_))));
  long seen = 0;
  for (int i = 0; i < kBins; ++i) {
    seen += bins_[static_cast<std::size_t>(i)];
    if (seen >= wanted) return std::min(kSmallest * std::pow(kRatio, i), max_);
  }
  return max_;
}

std::size_t RealTimePanel::compensated_actuators() const {
  std::size_t n = 0;
  for (const CompensatedBlock& b : setup_.compensators) n += b.actuators.size();
  return n;
}

nlohmann::json RealTimePanel::LiveCompensation() const {
  nlohmann::json compensation = nlohmann::json::object();
  std::size_t c = kRtColumns;
  for (const CompensatedBlock& b : setup_.compensators) {
    nlohmann::json actuators = nlohmann::json::array();
    double smallest = std::nan("");
    for (const std::string& name : b.actuators) {
      const double delay = last_[c++];
      if (std::isfinite(delay) && !(smallest <= delay)) smallest = delay;
      actuators.push_back({{"name", name}, {"delay_s", Number(delay)}});
    }
    compensation[b.name] = {{"delay_s", Number(smallest)}, {"actuators", std::move(actuators)}};
  }
  return compensation;
}

void RealTimePanel::Configure(RealTimeSetup setup) {
  setup_ = std::move(setup);
  last_.assign(columns(), std::nan(""));
  late_ = {};
  compute_ = {};
  recorded_ = nullptr;
}

void RealTimePanel::Add(std::span<const double> columns) {
  if (columns.empty() || columns.size() != last_.size()) return;
  const bool new_tick = !std::isfinite(last_[kRtTicks]) || columns[kRtTicks] != last_[kRtTicks];
  std::copy(columns.begin(), columns.end(), last_.begin());
  if (!new_tick) return;
  late_.Add(columns[kRtLate]);
  if (columns[kRtTicks] > 1) compute_.Add(columns[kRtCompute]);  // the previous tick's
}

void RealTimePanel::SetRecorded(nlohmann::json record) { recorded_ = std::move(record); }

nlohmann::json RealTimePanel::Json() const {
  if (recorded_.is_object()) {
    nlohmann::json j = recorded_;
    j["available"] = true;
    j["source"] = "recorded";
    j["paced"] = true;
    j["misses_in_a_row"] = columns() > 0 && std::isfinite(last_[kRtMissesInARow])
                               ? nlohmann::json(static_cast<long>(last_[kRtMissesInARow]))
                               : nlohmann::json();
    return j;
  }
  if (columns() == 0) {
    return {{"available", false}, {"paced", enabled()}, {"ticks", nullptr}, {"misses", nullptr}, {"J1_ms", nullptr},
            {"J2", nullptr}, {"J3", nullptr}};
  }
  auto count = [&](int c) {
    return std::isfinite(last_[std::size_t(c)]) ? nlohmann::json(static_cast<long>(last_[std::size_t(c)]))
                                                : nlohmann::json();
  };
  auto percentiles = [](const DurationHistogram& h) {
    return nlohmann::json{{"p50", h.Percentile(0.5)}, {"p99", h.Percentile(0.99)},
                          {"max", h.max()}, {"samples", h.count()}};
  };
  nlohmann::json actuators = nlohmann::json::array();
  const std::size_t first = kRtColumns + compensated_actuators();
  for (std::size_t k = 0; k < setup_.actuators.size(); ++k) {
    const std::size_t c = first + 3 * k;
    actuators.push_back({{"name", setup_.actuators[k]}, {"J1_ms", Number(last_[c])},
                         {"J2", Number(last_[c + 1])}, {"J3", Number(last_[c + 2])}});
  }
  return {{"available", true},
          {"source", "live"},
          {"paced", true},
          {"clock", setup_.clock},
          {"tick_s", setup_.tick},
          {"hold_after_misses", setup_.hold_after_misses},
          {"ticks", count(kRtTicks)},
          {"misses", count(kRtMisses)},
          {"misses_in_a_row", count(kRtMissesInARow)},
          {"max_consecutive_misses", count(kRtMaxInARow)},
          {"overruns", count(kRtOverruns)},
          {"late_s", percentiles(late_)},
          {"compute_s", percentiles(compute_)},
          // The first actuator's, J1 a running estimate over the last second.
          {"J1_ms", setup_.actuators.empty() ? nlohmann::json() : Number(last_[first])},
          {"J2", Number(last_[kRtJ2])},
          {"J3", Number(last_[kRtJ3])},
          {"compensation", LiveCompensation()},
          {"actuators", actuators}};
}

}  // namespace hybridtest::monitor
