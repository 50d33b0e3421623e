// PhysicalSubstructure: checkpoint state and the re-imposition on resume (see
// physical_substructure.h and docs/safety.md, "Resuming a run").
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "hybridtest/common/error.h"
#include "hybridtest/substructures/physical_substructure.h"
#include "hybridtest/substructures/resume_rules.h"

namespace hybridtest::substructures {

nlohmann::json PhysicalSubstructure::SaveState() const {
  return {{"last", {{"command_m", last_.command}, {"position_m", last_.position},
                    {"force_N", last_.force}, {"lab_time_s", last_.lab_time}}},
          {"evaluations", evaluations_},
          {"k0", k0_ ? nlohmann::json(*k0_) : nlohmann::json(nullptr)},
          {"safety", gate_.monitor().SaveState()},
          {"transfer", transfer_->SaveState()}};
}

void PhysicalSubstructure::RestoreState(const nlohmann::json& state) {
  try {
    const auto& last = state.at("last");
    last_ = {last.at("command_m").get<double>(), last.at("position_m").get<double>(),
             last.at("force_N").get<double>(), last.at("lab_time_s").get<double>()};
    evaluations_ = state.at("evaluations").get<long>();
    if (!state.at("k0").is_null()) k0_ = state.at("k0").get<double>();
    gate_.monitor().RestoreState(state.at("safety"));
    if (!state.at("transfer").is_null()) transfer_->RestoreState(state.at("transfer"));
  } catch (const nlohmann::json::exception& e) {
    throw Error(fmt::format("{}: cannot restore the saved state: {}", name_, e.what()));
  }
}

double PhysicalSubstructure::DefaultResumePositionTolerance() const {
  return substructures::DefaultResumePositionTolerance(gate_.monitor().limits());
}

double PhysicalSubstructure::DefaultResumeForceTolerance(double position_tolerance) const {
  return substructures::DefaultResumeForceTolerance(
      gate_.monitor().limits(), initial_stiffness().value_or(0.0), position_tolerance);
}

PhysicalSubstructure::ResumeCheck PhysicalSubstructure::ReimposeCommitted(
    double force_tolerance, double position_tolerance, long step,
    const std::function<void(bool)>& on_move) {
  const transfer::BenchUnits units = transfer_->bench_units();
  ResumeCheck check;
  check.command = last_.command;
  check.committed_position = last_.position;
  check.committed_force = last_.force;
  check.position_tolerance =
      position_tolerance > 0.0 ? position_tolerance : DefaultResumePositionTolerance();
  check.tolerance = force_tolerance > 0.0 ? force_tolerance
                                          : DefaultResumeForceTolerance(check.position_tolerance);
  // One move: checked before it is sent and after it is measured, like a trial (stage −1:
  // not a stage of the scheme).
  auto move = [&](double command, bool reimposition) {
    GatedMoveTo(command, {step, -1});
    if (on_move) on_move(reimposition);
  };
  if (const auto read = transfer_->Read()) {
    check.read_position = setup_.PositionMetres(read->position, units);
    check.read_force = setup_.ForceNewtons(read->force, units);
    // Every move from here is checked against where the actuator IS, not where the state says
    // it was: the increment limit then holds for the first move too.
    const double measured_command = *check.read_position;  // commands are actuator positions [m]
    gate_.monitor().SetStartPosition(measured_command);
    const double gap = check.command - measured_command;
    // The bench has moved since the commit: walk back in equal moves within max_increment.
    const int moves = ResumeMoves(gap, gate_.monitor().limits().max_increment);
    for (int k = 1; k < moves; ++k) {
      move(measured_command + gap * static_cast<double>(k) / moves, false);
      ++check.ramp_moves;
    }
  }
  move(check.command, true);
  check.position = last_.position;
  check.force = last_.force;
  const double position_difference = std::abs(check.position - check.committed_position);
  const double difference = std::abs(check.force - check.committed_force);
  if (!(position_difference <= check.position_tolerance) || !(difference <= check.tolerance)) {
    Hold();
    const bool position_bad = !(position_difference <= check.position_tolerance);
    throw transfer::SafetyStop(
        position_bad ? "resume_position_tolerance" : "resume_force_tolerance",
        position_bad ? position_difference : difference,
        position_bad ? check.position_tolerance : check.tolerance, step, -1, gate_.monitor().history(),
        fmt::format("{}: resume refused: the last committed command {} m was re-imposed and the "
                    "bench measured position {} m and force {} N, but the journal's committed "
                    "position is {} m and force {} N (differences {} m and {} N; accepted {} m "
                    "and {} N). The bench holds there. To proceed: check the specimen, the "
                    "actuator and the load cell; if the difference is understood, resume with "
                    "--position-tolerance M / --force-tolerance N (or resume.position_tolerance, "
                    "resume.force_tolerance)",
                    name_, check.command, check.position, check.force, check.committed_position,
                    check.committed_force, position_difference, difference,
                    check.position_tolerance, check.tolerance));
  }
  return check;
}

nlohmann::json PhysicalSubstructure::ReimposeForResume(const ResumeRequest& request) {
  if (request.commands_at_stop) NoteCommandsBeforeResume(*request.commands_at_stop);
  const ResumeCheck check = ReimposeCommitted(request.force_tolerance,
                                              request.position_tolerance, request.step,
                                              request.on_move);
  nlohmann::json c = {{"slot", request.name},     {"command_m", check.command},
                      {"committed_force_N", check.committed_force},
                      {"ramp_moves", check.ramp_moves}, {"position_m", check.position},
                      {"force_N", check.force},         {"tolerance_N", check.tolerance},
                      {"committed_position_m", check.committed_position},
                      {"position_tolerance_m", check.position_tolerance}};
  c["read_position_m"] = check.read_position ? nlohmann::json(*check.read_position) : nullptr;
  c["read_force_N"] = check.read_force ? nlohmann::json(*check.read_force) : nullptr;
  return nlohmann::json::array({c});
}

void PhysicalSubstructure::MeasureRequestedStiffness(nlohmann::json& entry) {
  if (!k0_ramp_) {
    Substructure::MeasureRequestedStiffness(entry);
    return;
  }
  const StiffnessMeasurement m = MeasureInitialStiffness(*k0_ramp_);
  nlohmann::json samples = nlohmann::json::array();
  for (const auto& [d, r] : m.samples) samples.push_back({d, r});
  entry.update({{"k0", m.k0}, {"source", "measured"}, {"amplitude_m", m.amplitude},
                {"samples_d_m_r_N", samples}});
}

}  // namespace hybridtest::substructures
