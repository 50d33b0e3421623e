// See rths_criteria.h.
#include "hybridtest/report/rths_criteria.h"

#include <fmt/core.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/common/tracking.h"
#include "hybridtest/report/json_text.h"

namespace hybridtest::report {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kTimeMatch = 1e-12;  // [s]
constexpr double kMaxDelay = 0.2;     // the longest tracking delay looked for [s]

// The run's setup of `slot` (p0 [m], sign, scale) from the config in its sidecar; the
// defaults where it says nothing.
void SlotSetup(const io::RunData& run, const std::string& slot, double& p0, double& sign,
               double& scale) {
  p0 = 0.0;
  sign = 1.0;
  scale = 1.0;
  const nlohmann::json& meta = run.metadata;
  if (!meta.is_object() || !meta.contains("config") || !meta["config"].is_string()) return;
  try {
    const YAML::Node setup =
        YAML::Load(meta["config"].get<std::string>())["substructures"][slot]["setup"];
    if (!setup.IsMap()) return;
    if (setup["p0"]) p0 = setup["p0"].as<double>();
    if (setup["sign"]) sign = setup["sign"].as<double>();
    if (setup["scale"]) scale = setup["scale"].as<double>();
  } catch (const YAML::Exception&) {
  }
}

// The model coordinate that `slot`'s displacement is, from the sidecar ("" if none).
std::string SlotCoordinate(const io::RunData& run, const std::string& slot) {
  const nlohmann::json& meta = run.metadata;
  if (!meta.is_object() || !meta.contains("model") || !meta["model"].contains("slots")) return "";
  for (const auto& s : meta["model"]["slots"]) {
    if (StringOr(s, "name") == slot) return StringOr(s, "coordinate");
  }
  return "";
}

// The run's coordinates in order (q1, q2, ... by the journal's channels).
std::vector<std::string> Coordinates(const io::RunData& run) {
  std::vector<std::string> q;
  for (const auto& c : run.channels) {
    if (io::ClassifyChannel(c.name).kind == io::ChannelKind::kCoordinate) q.push_back(c.name);
  }
  return q;
}

// `ref`'s channel at the times `t` (inside its span), linearly between its samples.
std::vector<double> Resample(const Eigen::VectorXd& tb, const Eigen::VectorXd& yb,
                             const std::vector<double>& t) {
  std::vector<double> y(t.size(), kNaN);
  Eigen::Index j = 0;
  const Eigen::Index nb = tb.size();
  for (std::size_t i = 0; i < t.size(); ++i) {
    while (j + 1 < nb && tb[j + 1] <= t[i] + kTimeMatch) ++j;
    if (std::abs(tb[j] - t[i]) <= kTimeMatch || j + 1 == nb) {
      y[i] = yb[j];
    } else {
      const double w = (t[i] - tb[j]) / (tb[j + 1] - tb[j]);
      y[i] = (1.0 - w) * yb[j] + w * yb[j + 1];
    }
  }
  return y;
}

}  // namespace

bool IsRealTimeRun(const io::RunData& run) {
  const nlohmann::json& meta = run.metadata;
  if (!meta.is_object()) return false;
  if (meta.contains("statistics") && meta["statistics"].is_object() &&
      meta["statistics"].contains("real_time")) {
    return true;
  }
  if (!meta.contains("config") || !meta["config"].is_string()) return false;
  try {
    return static_cast<bool>(YAML::Load(meta["config"].get<std::string>())["real_time"]);
  } catch (const YAML::Exception&) {
    return false;
  }
}

RthsCriteria ComputeRthsCriteria(const io::RunData& run, const io::RunData& reference) {
  RthsCriteria c;
  c.J.fill(kNaN);
  for (const auto& ch : run.channels) {
    const io::ChannelClass k = io::ClassifyChannel(ch.name);
    if (k.kind == io::ChannelKind::kPhysical && k.field == "position") {
      c.slot = k.slot;
      break;
    }
  }
  if (c.slot.empty()) {
    throw IoError(fmt::format("{}: no physical slot (no <slot>_position channel): the RTHS "
                              "criteria need a real-time run with one", run.csv_path));
  }
  // Floor 1: the slot's coordinate, or, where its displacement is not one coordinate, the
  // reference's own measured slot displacement. Floors 2 and 3: the first two other
  // coordinates.
  const std::string slot_coordinate = SlotCoordinate(run, c.slot);
  const bool ref_position = slot_coordinate.empty() && reference.Has(c.slot + "_position");
  c.floor[0] = ref_position ? c.slot + "_position" : slot_coordinate;
  std::size_t f = 1;
  for (const std::string& q : Coordinates(run)) {
    if (f < 3 && q != slot_coordinate) c.floor[f++] = q;
  }
  for (const std::string& name : c.floor) {
    if (!name.empty() && !reference.Has(name)) {
      throw IoError(fmt::format("{}: no channel {}: is it the reference of {} (the same model "
                                "run all-numerical)?", reference.csv_path, name, run.csv_path));
    }
  }
  // The run's committed rows (finite command and position) inside the reference's span.
  const Eigen::VectorXd t = run.Get("t"), xc = run.Get(c.slot + "_command"),
                        xm = run.Get(c.slot + "_position");
  const Eigen::VectorXd tb = reference.Get("t");
  std::vector<Eigen::Index> rows;
  for (Eigen::Index i = 0; i < t.size(); ++i) {
    if (std::isfinite(xc[i]) && std::isfinite(xm[i]) && t[i] >= tb[0] - kTimeMatch &&
        t[i] <= tb[tb.size() - 1] + kTimeMatch) {
      rows.push_back(i);
    }
  }
  if (rows.size() < 2) {
    throw IoError(fmt::format("{} and {}: fewer than two of the run's rows lie in the "
                              "reference's time span", run.csv_path, reference.csv_path));
  }
  c.points = static_cast<long>(rows.size());
  std::vector<double> tt, c_cmd, c_pos;
  for (Eigen::Index i : rows) {
    tt.push_back(t[i]);
    c_cmd.push_back(xc[i]);
    c_pos.push_back(xm[i]);
  }
  // J1–J3: the actuator's tracking.
  const double tick = (tt.back() - tt.front()) / static_cast<double>(tt.size() - 1);
  c.J[1] = TrackingDelayMs(c_pos, c_cmd, tick, kMaxDelay);
  c.J[2] = NormalisedRmsError(c_pos, c_cmd);
  c.J[3] = PeakError(c_pos, c_cmd);
  // J4, J5: floor 1, the slot's measured displacement against the reference.
  if (!c.floor[0].empty()) {
    double p0, sign, scale;
    SlotSetup(run, c.slot, p0, sign, scale);
    std::vector<double> dm(c_pos.size());
    for (std::size_t i = 0; i < dm.size(); ++i) dm[i] = (c_pos[i] - p0) / (sign * scale);
    std::vector<double> y1 = Resample(tb, reference.Get(c.floor[0]), tt);
    if (ref_position) {
      double rp0, rsign, rscale;
      SlotSetup(reference, c.slot, rp0, rsign, rscale);
      for (double& y : y1) y = (y - rp0) / (rsign * rscale);
    }
    c.J[4] = NormalisedRmsError(dm, y1);
    c.J[5] = PeakError(dm, y1);
  }
  // J6–J9: floors 2 and 3, the run's response against the reference's.
  for (std::size_t k = 1; k < 3; ++k) {
    if (c.floor[k].empty()) continue;
    const Eigen::VectorXd yall = run.Get(c.floor[k]);
    std::vector<double> y;
    for (Eigen::Index i : rows) y.push_back(yall[i]);
    const std::vector<double> yref = Resample(tb, reference.Get(c.floor[k]), tt);
    c.J[5 + k] = NormalisedRmsError(y, yref);  // J6, J7
    c.J[7 + k] = PeakError(y, yref);           // J8, J9
  }
  return c;
}

std::string FormatRthsCriteria(const RthsCriteria& c) {
  auto v = [](double x) { return std::isfinite(x) ? fmt::format("{:.4g}", x) : std::string("—"); };
  auto floor = [&](std::size_t f) { return c.floor[f].empty() ? std::string("—") : c.floor[f]; };
  std::string s = fmt::format(
      "RTHS criteria (vRTHS benchmark) of slot {} against the reference structure, {} points:\n",
      c.slot, c.points);
  s += fmt::format("  J1 = {} ms  tracking delay (cross-correlation of position and command)\n",
                   v(c.J[1]));
  s += fmt::format("  J2 = {} %   NRMS tracking error      J3 = {} %  peak tracking error\n",
                   v(c.J[2]), v(c.J[3]));
  s += fmt::format("  J4 = {} %   NRMS error, floor 1 ({}, measured)   J5 = {} %  peak\n",
                   v(c.J[4]), floor(0), v(c.J[5]));
  s += fmt::format("  J6 = {} %   NRMS error, floor 2 ({})   J7 = {} %  floor 3 ({})\n",
                   v(c.J[6]), floor(1), v(c.J[7]), floor(2));
  s += fmt::format("  J8 = {} %   peak error, floor 2        J9 = {} %  floor 3\n", v(c.J[8]),
                   v(c.J[9]));
  return s;
}

nlohmann::json ToJson(const RthsCriteria& c) {
  auto num = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); };
  nlohmann::json j = {{"slot", c.slot}, {"floors", c.floor}, {"points", c.points},
                      {"J1_ms", num(c.J[1])}};
  for (int k = 2; k <= 9; ++k) j[fmt::format("J{}", k)] = num(c.J[static_cast<std::size_t>(k)]);
  return j;
}

}  // namespace hybridtest::report
