// plan's checks and advice that are not candidate runs (plan.h): the reference against the
// safety limits, what a force reversal within a move means, and the spec once per noise seed.
#include <fmt/core.h>

#include <cmath>

#include "hybridtest/multibody/kane.h"
#include "hybridtest/runner/plan.h"
#include "hybridtest/substructures/twin.h"

namespace hybridtest::runner {
namespace {

// The first row where |value| (or value itself, for a one-sided limit) passes `limit`.
struct Excess {
  bool found = false;
  double value = 0.0;
  double t = 0.0;
};

void Note(Excess& e, bool beyond, double value, double t) {
  if (beyond && !e.found) e = {true, value, t};
}

}  // namespace

std::vector<PlanWarning> ReferenceLimitWarnings(const io::RunSpec& spec,
                                                const io::RunData& reference) {
  const multibody::Model& model = spec.model.model;
  const int n = model.num_coordinates();
  const int m = model.num_slots();
  multibody::Data<double> data(model);
  std::vector<Eigen::VectorXd> q_cols;
  for (const auto& c : model.coordinates()) q_cols.push_back(reference.Get(c.name));
  const Eigen::VectorXd t = reference.Get("t");
  std::vector<PlanWarning> warnings;
  for (int s = 0; s < m && s < static_cast<int>(spec.substructures.size()); ++s) {
    const auto& physical = spec.substructures[static_cast<std::size_t>(s)].physical;
    if (!physical) continue;
    const std::string& slot = model.slots()[static_cast<std::size_t>(s)].info.name;
    const Eigen::VectorXd r = reference.Get(slot);
    const auto& setup = physical->setup;
    const auto& lim = physical->limits;
    Excess stroke_max, stroke_min, soft, hard;
    Eigen::VectorXd q(n), d(m);
    for (long k = 0; k < reference.num_rows(); ++k) {
      for (int i = 0; i < n; ++i) q(i) = q_cols[static_cast<std::size_t>(i)](k);
      multibody::CalcSlotDisplacements<double>(model, data, t(k), q, d);
      const double command = setup.CommandMetres(d(s));
      // The measured force [N] (after the load-cell zero) that gives this restoring force.
      const double force = r(k) / (setup.force_sign * setup.force_scale);
      Note(stroke_max, command > lim.stroke_max, command, t(k));
      Note(stroke_min, command < lim.stroke_min, command, t(k));
      Note(soft, std::abs(force) > lim.force_soft, force, t(k));
      Note(hard, std::abs(force) > lim.force_hard, force, t(k));
    }
    auto add = [&](const Excess& e, const char* limit, double limit_value, const char* unit,
                   const char* what) {
      if (!e.found) return;
      PlanWarning w{slot, limit, e.value, limit_value, e.t, ""};
      w.message = fmt::format(
          "the reference itself reaches {} = {:.4g} {} at t = {:.3g} s, beyond "
          "substructures.{}.safety.{} = {:.4g} {}: every candidate will stop there, whatever "
          "its scheme or step. {}",
          what, e.value, unit, e.t, slot, limit, limit_value, unit,
          std::string(limit).starts_with("force")
              ? "Lower the load on the model, or raise the limit if the specimen and the "
                "actuator can take that force"
              : "Lower the load on the model, or move p0 / the stroke limits if the actuator "
                "can reach that position");
      warnings.push_back(std::move(w));
    };
    add(stroke_max, "stroke_max", lim.stroke_max, "m", "the actuator command");
    add(stroke_min, "stroke_min", lim.stroke_min, "m", "the actuator command");
    // force_hard implies force_soft: name the harder one only.
    if (hard.found) {
      add(hard, "force_hard", lim.force_hard, "N", "the specimen force");
    } else {
      add(soft, "force_soft", lim.force_soft, "N", "the predicted specimen force");
    }
  }
  return warnings;
}

std::vector<io::RunSpec> SeededSpecs(const io::RunSpec& spec, const std::vector<unsigned long>& seeds) {
  // The substructures on a noisy emulated bench (the builders know which).
  std::vector<std::size_t> noisy;
  for (std::size_t s = 0; s < spec.substructures.size(); ++s) {
    const auto& physical = spec.substructures[s].physical;
    if (physical && substructures::ReseededTransfer(physical->transfer, 0)) noisy.push_back(s);
  }
  if (noisy.empty() || seeds.empty()) return {spec};
  std::vector<io::RunSpec> out;
  for (const unsigned long seed : seeds) {
    io::RunSpec seeded = spec;
    for (const std::size_t s : noisy) {
      seeded.substructures[s].physical->transfer =
          *substructures::ReseededTransfer(spec.substructures[s].physical->transfer, seed);
    }
    out.push_back(std::move(seeded));
  }
  return out;
}

std::string ForceReversalAdvice(const PlanResult& r) {
  if (r.force_reversals <= 0) return "";
  return fmt::format(
      "{}: the specimen force reversed {} times within moves: the actuator overshoots its "
      "targets, and a hysteretic specimen ratchets on every small unloading, an error floor no "
      "scheme or step removes. Approach each target from the direction of motion: on an "
      "emulated bench `actuator: {{approach: monotone}}`; on a real controller a monotone "
      "final approach (docs/lab-time.md)",
      r.candidate.label, r.force_reversals);
}

}  // namespace hybridtest::runner
