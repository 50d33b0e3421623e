// See fmu_plant.h.
#include "hybridtest/fmi/fmu_plant.h"

#include <fmt/core.h>

#include <cmath>
#include <filesystem>

#include "hybridtest/common/error.h"
#include "hybridtest/fmi/fmu_archive.h"
#include "hybridtest/fmi/fmu_config.h"
#include "hybridtest/fmi/fmu_units.h"

namespace hybridtest::fmi {
namespace {

std::vector<std::string> Names(const YamlInput& in, const YAML::Node& node, const std::string& kp,
                               const char* what) {
  std::vector<std::string> names;
  if (node && node.IsScalar()) {
    names.push_back(node.Scalar());
  } else if (node && node.IsSequence() && node.size() > 0) {
    for (const auto& n : node) names.push_back(in.String(n, kp, what));
  } else {
    in.ThrowValue(node, kp, fmt::format("the {} (a name, or a list of one per actuator)", what));
  }
  return names;
}

}  // namespace

FmuPlant::FmuPlant(std::shared_ptr<const FmuPlantBinding> binding, LogSink log)
    : binding_(std::move(binding)), log_(std::move(log)) {
  for (const auto* v : binding_->command) command_vr_.push_back(v->value_reference);
  last_command_.assign(binding_->command.size(), 0.0);
}

FmuPlant::~FmuPlant() {
  fmu_.reset();
  if (!dir_.empty()) {
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
  }
}

void FmuPlant::Load() {
  if (fmu_) return;
  dir_ = MakeUnpackDir();
  ExtractArchive(binding_->fmu, dir_);
  fmu_ = LoadFmu(dir_, binding_->md, binding_->fmu, "plant", log_);
  fmu_->Initialize(0.0, binding_->parameters);
}

void FmuPlant::Activate() {
  Load();
  active_ = true;
}

std::string FmuPlant::Describe() const {
  return fmt::format("FMU plant {} ({}, FMI {}, {} actuator{})", binding_->fmu,
                     binding_->md.model_name, binding_->md.fmi_version, num_actuators(),
                     num_actuators() == 1 ? "" : "s");
}

void FmuPlant::StartPaced(double /*tick*/, const Clock& clock) {
  clock_ = &clock;
  paced_origin_ = clock.Now() - t_;
}

// Steps the FMU by `step` while a whole step fits before `until` [s].
void FmuPlant::Advance(double until) {
  const double h = binding_->step;
  const long steps = static_cast<long>(std::floor((until - t_) / h + 1e-9));
  for (long k = 0; k < steps; ++k) {
    fmu_->DoStep(t_, h);
    t_ += h;
  }
}

std::vector<transfer::Measurement> FmuPlant::Read() const {
  const std::size_t n = binding_->command.size();
  std::vector<unsigned> vr;
  for (const auto* v : binding_->force) vr.push_back(v->value_reference);
  for (const auto* v : binding_->position) {
    if (v != nullptr) vr.push_back(v->value_reference);
  }
  std::vector<double> values(vr.size());
  fmu_->GetReal(vr, values);
  std::vector<transfer::Measurement> out(n);
  std::size_t p = n;
  for (std::size_t k = 0; k < n; ++k) {
    out[k].force = binding_->force_factor[k] * values[k] + binding_->force_offset[k];
    out[k].position = binding_->position[k] != nullptr
                          ? binding_->position_factor[k] * values[p++] + binding_->position_offset[k]
                          : last_command_[k];
    out[k].lab_time = t_;
  }
  return out;
}

void FmuPlant::Execute(std::span<const double> commands, std::span<transfer::Measurement> out) {
  const std::size_t n = binding_->command.size();
  if (commands.size() != n || out.size() != n) {
    throw TransferError(fmt::format("{}: {} commands and {} measurements given for {} actuators",
                                    Describe(), commands.size(), out.size(), n));
  }
  if (!active_ || !fmu_) throw TransferError(Describe() + ": Execute while not active (held)");
  std::vector<double> values(n);
  for (std::size_t k = 0; k < n; ++k) {
    values[k] = (commands[k] - binding_->command_offset[k]) / binding_->command_factor[k];
    last_command_[k] = commands[k];
  }
  fmu_->SetReal(command_vr_, values);
  ++commands_;
  Advance(clock_ != nullptr ? clock_->Now() - paced_origin_ : t_ + binding_->move_time);
  const auto m = Read();
  std::copy(m.begin(), m.end(), out.begin());
}

std::optional<std::vector<transfer::Measurement>> FmuPlant::ReadAll() {
  if (!fmu_) return std::nullopt;
  try {
    return Read();
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

nlohmann::json FmuPlant::SaveState() const {
  nlohmann::json state{{"t", t_}, {"commands", commands_}, {"last_command", last_command_}};
  if (fmu_ && binding_->md.can_serialize_state) {
    fmu_->SnapshotState();
    state["fmu_state"] = ToHex(fmu_->SerializeSnapshot());
  }
  return state;
}

void FmuPlant::RestoreState(const nlohmann::json& state) {
  Load();
  if (!state.is_object() || !state.contains("t")) {
    throw Error(fmt::format("{}: the saved state is not an FMU plant's", binding_->fmu));
  }
  const double t = state["t"].get<double>();
  if (state.contains("fmu_state")) {
    fmu_->DeserializeIntoSnapshot(FromHex(state["fmu_state"].get<std::string>()));
    fmu_->RestoreSnapshot();
  } else if (!binding_->md.DeclaresNoState()) {
    throw Error(fmt::format("{}: cannot resume: the plant FMU keeps a state but cannot "
                            "serialize it (canSerializeFMUstate is false); run again from the "
                            "start, or export the FMU with state serialization", binding_->fmu));
  } else {
    Advance(t);  // a plant without state: only its time
  }
  t_ = t;
  commands_ = state.value("commands", 0L);
  last_command_ = state.value("last_command", last_command_);
}

substructures::TransferSpec ParseFmuPlant(const YamlInput& in, const YAML::Node& node,
                                          const std::string& kp, std::string* fmu_file) {
  in.CheckKeys(node, kp, {"type", "fmu", "command", "position", "force", "parameters",
                          "move_time", "step"});
  auto b = std::make_shared<FmuPlantBinding>();
  b->fmu = ReadFmuFile(in, node, kp, &b->md);
  const ModelDescription& md = b->md;
  const auto commands = Names(in, node["command"], kp + ".command", "FMU inputs of the commands");
  const auto forces = Names(in, node["force"], kp + ".force", "FMU outputs of the forces");
  std::vector<std::string> positions;
  if (node["position"]) {
    positions = Names(in, node["position"], kp + ".position", "FMU outputs of the positions");
  }
  const std::size_t n = commands.size();
  if (forces.size() != n || (!positions.empty() && positions.size() != n)) {
    throw ConfigError(fmt::format("{}: {}: {} commands, {} forces and {} positions: give one of "
                                  "each per actuator", in.Where(node, kp), b->fmu, n,
                                  forces.size(), positions.size()));
  }
  for (std::size_t k = 0; k < n; ++k) {
    const auto& c = Require(in, node["command"], kp + ".command", b->fmu, md, commands[k],
                            "input", "an actuator command");
    const auto& f = Require(in, node["force"], kp + ".force", b->fmu, md, forces[k], "output",
                            "a load-cell force");
    const UnitCheck cu = CheckSlotUnits(md, c, f, b->fmu);
    b->command.push_back(&c);
    b->force.push_back(&f);
    b->command_factor.push_back(cu.in_factor);
    b->command_offset.push_back(cu.in_offset);
    b->force_factor.push_back(cu.out_factor);
    b->force_offset.push_back(cu.out_offset);
    const ModelVariable* p = nullptr;
    UnitCheck pu;
    if (!positions.empty()) {
      p = &Require(in, node["position"], kp + ".position", b->fmu, md, positions[k], "output",
                   "a measured position");
      pu = CheckSlotUnits(md, *p, f, b->fmu);
    }
    b->position.push_back(p);
    b->position_factor.push_back(pu.in_factor);
    b->position_offset.push_back(pu.in_offset);
  }
  b->parameters = ReadParameters(in, node["parameters"], kp + ".parameters", b->fmu, md);
  if (node["move_time"]) {
    b->move_time = in.Number(node["move_time"], kp + ".move_time", "the lab time of one move in s (> 0)");
  }
  if (node["step"]) b->step = in.Number(node["step"], kp + ".step", "the FMU's step in s (> 0)");
  if (!(b->step > 0.0) || !(b->move_time >= b->step)) {
    throw ConfigError(fmt::format("{}: {}: step = {} s and move_time = {} s: give 0 < step <= "
                                  "move_time", in.Where(node, kp), b->fmu, b->step, b->move_time));
  }
  if (fmu_file != nullptr) *fmu_file = b->fmu;
  return {"fmu", [b]() -> std::unique_ptr<transfer::TransferSystem> {
            return std::make_unique<FmuPlant>(b);
          }};
}

}  // namespace hybridtest::fmi
