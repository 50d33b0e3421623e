// PhysicalSubstructure: where every actuator is before a run or a resume moves it, and the
// walk from there (see physical_substructure.h, substructure.h's CheckStart and
// docs/safety.md, "The start of a run").
#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "hybridtest/common/error.h"
#include "hybridtest/substructures/physical_substructure.h"
#include "hybridtest/substructures/resume_rules.h"

namespace hybridtest::substructures {

std::optional<std::vector<double>> PhysicalSubstructure::ReadPositions(
    std::vector<double>* forces) {
  const auto n = static_cast<std::size_t>(num_actuators());
  const auto read = transfer_->ReadAll();
  if (!read || read->size() != n) return std::nullopt;
  const transfer::BenchUnits units = transfer_->bench_units();
  std::vector<double> measured(n);
  if (forces != nullptr) forces->resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    measured[k] = (*read)[k].position * units.metres_per_length_unit;
    if (forces != nullptr) {
      (*forces)[k] = (*read)[k].force * units.newtons_per_force_unit - zeros_[k];
    }
    // Every move from here is checked against where the actuator is, not where it should be:
    // the increment limit then holds for the first move too.
    gate_.monitor(static_cast<int>(k)).SetStartPosition(measured[k]);
  }
  return measured;
}

int PhysicalSubstructure::WalkTo(const std::vector<double>& from, const std::vector<double>& to,
                                 long step, const std::function<void()>& on_move) {
  const std::size_t n = from.size();
  int moves = 1;
  for (std::size_t k = 0; k < n; ++k) {
    moves = std::max(moves, ResumeMoves(to[k] - from[k],
                                        gate_.monitor(static_cast<int>(k)).limits().max_increment));
  }
  std::vector<double> ramp(n);
  for (int j = 1; j < moves; ++j) {
    for (std::size_t k = 0; k < n; ++k) {
      ramp[k] = from[k] + (to[k] - from[k]) * static_cast<double>(j) / moves;
    }
    MoveAll(ramp, {step, -1});
    if (on_move) on_move();
  }
  return moves - 1;
}

nlohmann::json PhysicalSubstructure::CheckStart(const StartRequest& request) {
  const int n = num_actuators();
  const auto nz = static_cast<std::size_t>(n);
  // The first command: the setup's at d0, or at d = 0 when the K0 ramp moves first.
  Eigen::VectorXd d = Eigen::VectorXd::Zero(num_slots());
  if (!k0_ramp_) {
    for (Eigen::Index i = 0; i < d.size() && i < static_cast<Eigen::Index>(request.d0.size());
         ++i) {
      d(i) = request.d0[static_cast<std::size_t>(i)];
    }
  }
  Eigen::VectorXd first(n);
  setup_->CalcCommands(d, first);
  nlohmann::json record = {{"slot", request.name}, {"ramp", request.ramp}};
  const auto measured = ReadPositions();
  if (!measured) {
    record["read"] = false;
    record["note"] = fmt::format(
        "{} cannot read its position without moving: the first command was checked against "
        "the setup's p0 only", transfer_->Describe());
    return record;
  }
  record["read"] = true;
  const transfer::BenchUnits units = transfer_->bench_units();
  const bool other_unit = units.metres_per_length_unit != 1.0;
  auto in_bench = [&](double metres) {
    return other_unit ? fmt::format(" ({:.6g} {})", metres / units.metres_per_length_unit,
                                    units.length_name)
                      : std::string();
  };
  nlohmann::json actuators = nlohmann::json::array();
  std::vector<double> to(nz);
  bool beyond = false;  // some actuator is farther than its max_increment
  for (int k = 0; k < n; ++k) {
    const auto kz = static_cast<std::size_t>(k);
    const double at = (*measured)[kz], p0 = setup_->p0()(k);
    to[kz] = first(k);
    const double gap = std::abs(to[kz] - at);
    const double limit = gate_.monitor(k).limits().max_increment;
    actuators.push_back({{"actuator", k + 1}, {"read_position_m", at},
                         {"first_command_m", to[kz]}, {"p0_m", p0}, {"gap_m", gap},
                         {"max_increment_m", limit}});
    if (gap <= limit) continue;
    beyond = true;
    if (request.ramp) continue;
    // Refused before anything moved: the first command would jump.
    const std::string who =
        n == 1 ? request.name : fmt::format("{} actuator {}", request.name, k + 1);
    throw transfer::SafetyStop(
        "start_position", gap, limit, 0, 0, gate_.monitor(k).history(),
        fmt::format("{}: the actuator is at {:.6g} m{}, but the run's first command is {:.6g} m "
                    "(p0 = {:.6g} m{} plus the initial displacement): {:.6g} m apart, beyond "
                    "safety.max_increment = {:.6g} m. Refused before anything moved. To go on, "
                    "either move the actuator to p0 and start again, or add `start: ramp` to "
                    "the run config to ramp from where it is to the first command in steps "
                    "within max_increment",
                    who, at, in_bench(at), to[kz], p0, in_bench(p0), gap, limit));
  }
  record["actuators"] = actuators;
  int moves = 0;
  if (request.ramp && beyond) {
    moves = WalkTo(*measured, to, 0, request.on_move);
    // The ramp ends on the first command itself (the run's first trial then repeats it).
    MoveAll(to, {0, -1});
    if (request.on_move) request.on_move();
    ++moves;
  }
  record["ramp_moves"] = moves;
  return record;
}

}  // namespace hybridtest::substructures
