// PhysicalSubstructure::ReimposeCommitted: a resume starts from where every actuator IS (see
// physical_substructure.h and docs/safety.md, "Resuming a run").
#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "hybridtest/common/error.h"
#include "hybridtest/substructures/physical_substructure.h"
#include "hybridtest/substructures/resume_rules.h"
#include "hybridtest/substructures/substructure_spec.h"

namespace hybridtest::substructures {

double PhysicalSubstructure::DefaultResumePositionTolerance(int k) const {
  return substructures::DefaultResumePositionTolerance(gate_.monitor(k).limits());
}

double PhysicalSubstructure::DefaultResumeForceTolerance(double position_tolerance, int k) const {
  // K_a,kk: the stiffness the gate predicts this actuator's force with, if known.
  const auto i = static_cast<Eigen::Index>(k);
  const double stiffness = actuator_k_ ? (*actuator_k_)(i, i) : safety_stiffness_.value_or(0.0);
  return substructures::DefaultResumeForceTolerance(gate_.monitor(k).limits(), stiffness,
                                                    position_tolerance);
}

PhysicalSubstructure::ResumeCheck PhysicalSubstructure::ReimposeCommitted(
    double force_tolerance, double position_tolerance, long step,
    const std::function<void(bool)>& on_move) {
  const std::size_t n = last_.size();
  ResumeCheck check;
  check.actuators.resize(n);
  std::vector<double> committed(n);
  for (std::size_t k = 0; k < n; ++k) {
    ResumeCheck::Actuator& a = check.actuators[k];
    a.command = committed[k] = last_[k].command;
    a.committed_position = last_[k].position;
    a.committed_force = last_[k].force;
    a.position_tolerance = position_tolerance > 0.0
                               ? position_tolerance
                               : DefaultResumePositionTolerance(static_cast<int>(k));
    a.force_tolerance =
        force_tolerance > 0.0
            ? force_tolerance
            : DefaultResumeForceTolerance(a.position_tolerance, static_cast<int>(k));
  }
  auto move = [&](const std::vector<double>& commands, bool reimposition) {
    MoveAll(commands, {step, -1});
    if (on_move) on_move(reimposition);
  };
  std::vector<double> read_force;
  if (const auto measured = ReadPositions(&read_force)) {
    for (std::size_t k = 0; k < n; ++k) {
      check.actuators[k].read_position = (*measured)[k];
      check.actuators[k].read_force = read_force[k];
    }
    check.ramp_moves = WalkTo(*measured, committed, step, [&] {
      if (on_move) on_move(false);
    });
  }
  move(committed, true);
  for (std::size_t k = 0; k < n; ++k) {
    ResumeCheck::Actuator& a = check.actuators[k];
    a.position = last_[k].position;
    a.force = last_[k].force;
    const double dp = std::abs(a.position - a.committed_position);
    const double df = std::abs(a.force - a.committed_force);
    const bool position_bad = !(dp <= a.position_tolerance);
    if (!position_bad && df <= a.force_tolerance) continue;
    Hold();
    throw transfer::SafetyStop(
        position_bad ? "resume_position_tolerance" : "resume_force_tolerance",
        position_bad ? dp : df, position_bad ? a.position_tolerance : a.force_tolerance, step,
        -1, gate_.monitor(static_cast<int>(k)).history(),
        fmt::format("{}: resume refused: actuator {}'s last committed command {} m was "
                    "re-imposed and it measured position {} m and force {} N, but the "
                    "journal's committed position is {} m and force {} N (differences {} m and "
                    "{} N; accepted {} m and {} N). Every actuator holds there. To proceed: "
                    "check the specimen, the actuators and the load cells; if the difference is "
                    "understood, resume with --position-tolerance M / --force-tolerance N (or "
                    "resume.position_tolerance, resume.force_tolerance)",
                    name_, k + 1, a.command, a.position, a.force, a.committed_position,
                    a.committed_force, dp, df, a.position_tolerance, a.force_tolerance));
  }
  return check;
}

nlohmann::json PhysicalSubstructure::ReimposeForResume(const ResumeRequest& request) {
  // Every actuator walked back from where it is and re-imposed together; every position and
  // force checked. One record per actuator, named like its channels.
  const ResumeCheck check = ReimposeCommitted(request.force_tolerance,
                                              request.position_tolerance, request.step,
                                              request.on_move);
  nlohmann::json out = nlohmann::json::array();
  const std::size_t n = check.actuators.size();
  for (std::size_t k = 0; k < n; ++k) {
    const auto& a = check.actuators[k];
    const std::string slot = ActuatorName(request.name, static_cast<int>(k), static_cast<int>(n));
    nlohmann::json c = {{"slot", slot},
                        {"command_m", a.command},
                        {"committed_force_N", a.committed_force},
                        {"ramp_moves", check.ramp_moves},
                        {"position_m", a.position},
                        {"force_N", a.force},
                        {"tolerance_N", a.force_tolerance},
                        {"committed_position_m", a.committed_position},
                        {"position_tolerance_m", a.position_tolerance}};
    if (n > 1) c["actuator"] = k + 1;
    c["read_position_m"] = a.read_position ? nlohmann::json(*a.read_position) : nullptr;
    c["read_force_N"] = a.read_force ? nlohmann::json(*a.read_force) : nullptr;
    out.push_back(c);
  }
  return out;
}

}  // namespace hybridtest::substructures
