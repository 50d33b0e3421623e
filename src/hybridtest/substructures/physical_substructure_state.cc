// PhysicalSubstructure: checkpoint state and the re-imposition on resume (see
// physical_substructure.h and docs/safety.md, "Resuming a run").
#include <fmt/format.h>

#include <cmath>

#include "hybridtest/common/error.h"
#include "hybridtest/substructures/physical_substructure.h"

namespace hybridtest::substructures {

nlohmann::json PhysicalSubstructure::SaveState() const {
  return {{"last", {{"command_m", last_.command}, {"position_m", last_.position},
                    {"force_N", last_.force}, {"lab_time_s", last_.lab_time}}},
          {"evaluations", evaluations_},
          {"k0", k0_ ? nlohmann::json(*k0_) : nlohmann::json(nullptr)},
          {"safety", safety_.SaveState()},
          {"transfer", transfer_->SaveState()}};
}

void PhysicalSubstructure::RestoreState(const nlohmann::json& state) {
  try {
    const auto& last = state.at("last");
    last_ = {last.at("command_m").get<double>(), last.at("position_m").get<double>(),
             last.at("force_N").get<double>(), last.at("lab_time_s").get<double>()};
    evaluations_ = state.at("evaluations").get<long>();
    if (!state.at("k0").is_null()) k0_ = state.at("k0").get<double>();
    safety_.RestoreState(state.at("safety"));
    if (!state.at("transfer").is_null()) transfer_->RestoreState(state.at("transfer"));
  } catch (const nlohmann::json::exception& e) {
    throw Error(fmt::format("{}: cannot restore the saved state: {}", name_, e.what()));
  }
}

PhysicalSubstructure::ResumeCheck PhysicalSubstructure::ReimposeCommitted(
    double force_tolerance, long step, const std::function<void(bool)>& on_move) {
  const transfer::BenchUnits units = transfer_->bench_units();
  ResumeCheck check;
  check.command = last_.command;
  check.committed_force = last_.force;
  check.tolerance = force_tolerance > 0.0 ? force_tolerance : 0.01 * safety_.limits().force_hard;
  // One move: checked before it is sent and after it is measured, like a trial (stage −1:
  // not a stage of the scheme).
  auto move = [&](double command, bool reimposition) {
    held_ = false;
    try {
      safety_.CheckCommand(command, step, -1);
      const transfer::Measurement m = transfer_->Execute(setup_.ToBench(command, units));
      ++evaluations_;
      last_ = {command, setup_.PositionMetres(m.position, units),
               setup_.ForceNewtons(m.force, units), m.lab_time};
      safety_.CheckMeasurement(command, last_.position, last_.force, step, -1);
    } catch (...) {
      Hold();
      throw;
    }
    if (on_move) on_move(reimposition);
  };
  if (const auto read = transfer_->Read()) {
    check.read_position = setup_.PositionMetres(read->position, units);
    check.read_force = setup_.ForceNewtons(read->force, units);
    const double gap = check.command - *check.read_position;
    const double limit = safety_.limits().max_increment;
    if (std::abs(gap) > limit) {
      // The bench has moved since the commit: walk back in equal moves within the limit,
      // starting from where it is.
      const int moves = static_cast<int>(std::ceil(std::abs(gap) / limit));
      safety_.SetStartPosition(*check.read_position);
      for (int k = 1; k < moves; ++k) {
        move(*check.read_position + gap * static_cast<double>(k) / moves, false);
        ++check.ramp_moves;
      }
    }
  }
  move(check.command, true);
  check.position = last_.position;
  check.force = last_.force;
  const double difference = std::abs(check.force - check.committed_force);
  if (!(difference <= check.tolerance)) {
    Hold();
    throw transfer::SafetyStop(
        "resume_force_tolerance", difference, check.tolerance, step, -1, safety_.history(),
        fmt::format("{}: resume refused: the last committed command {} m was re-imposed and the "
                    "bench measured {} N, but the journal's committed force is {} N (difference "
                    "{} N > resume.force_tolerance {} N). The bench holds there. To proceed: "
                    "check the specimen and the load cell; if the difference is understood, "
                    "resume with --force-tolerance N or set resume.force_tolerance",
                    name_, check.command, check.force, check.committed_force, difference,
                    check.tolerance));
  }
  return check;
}

}  // namespace hybridtest::substructures
