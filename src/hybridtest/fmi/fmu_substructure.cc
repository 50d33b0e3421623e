// See fmu_substructure.h.
#include "hybridtest/fmi/fmu_substructure.h"

#include <fmt/core.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "hybridtest/common/error.h"
#include "hybridtest/fmi/fmu_archive.h"

namespace hybridtest::fmi {

FmuSubstructure::FmuSubstructure(std::shared_ptr<const FmuBinding> binding, LogSink log)
    : binding_(std::move(binding)), dir_(MakeUnpackDir()) {
  try {
    ExtractArchive(binding_->fmu, dir_);
    fmu_ = LoadFmu(dir_, binding_->md, binding_->fmu, binding_->name, std::move(log));
    fmu_->Initialize(0.0, binding_->parameters);
    if (!binding_->stateless) fmu_->SnapshotState();
  } catch (...) {
    fmu_.reset();
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
    throw;
  }
  for (const auto* v : binding_->inputs) in_vr_.push_back(v->value_reference);
  for (const auto* v : binding_->outputs) out_vr_.push_back(v->value_reference);
  in_.resize(in_vr_.size());
  out_.resize(out_vr_.size());
}

FmuSubstructure::~FmuSubstructure() {
  fmu_.reset();  // the library is unloaded before its file goes
  std::error_code ignored;
  std::filesystem::remove_all(dir_, ignored);
}

void FmuSubstructure::Trial(std::span<const double> d, std::span<double> r,
                            const substructures::TrialContext& context) {
  // A stage time within rounding of the committed time is the committed time (t_n = n·dt
  // and t_(n-1) + dt differ in the last bits).
  const double tolerance = 1e-9 * (1.0 + std::abs(t_committed_));
  double h = context.t - t_committed_;
  if (std::abs(h) <= tolerance) h = 0.0;
  if (h < 0.0) {
    throw Error(fmt::format("{}: a trial at t = {} s before the committed time {} s",
                            binding_->fmu, context.t, t_committed_));
  }
  const auto& b = *binding_;
  for (std::size_t k = 0; k < in_.size(); ++k) {
    in_[k] = (d[k] - b.in_offset[k]) / b.in_factor[k];
  }
  if (!b.stateless && moved_) fmu_->RestoreSnapshot();
  fmu_->SetReal(in_vr_, in_);
  if (!b.stateless && h > 0.0) {
    fmu_->DoStep(t_committed_, h);
    ++steps_;
  }
  moved_ = true;
  fmu_->GetReal(out_vr_, out_);
  for (std::size_t k = 0; k < out_.size(); ++k) {
    r[k] = b.out_factor[k] * out_[k] + b.out_offset[k];
  }
  t_trial_ = t_committed_ + h;
}

void FmuSubstructure::Commit() {
  if (!moved_) return;
  if (binding_->stateless) {
    if (t_trial_ > t_committed_) {
      fmu_->DoStep(t_committed_, t_trial_ - t_committed_);
      ++steps_;
    }
  } else {
    fmu_->SnapshotState();
  }
  t_committed_ = t_trial_;
  moved_ = false;
}

std::string FmuSubstructure::Describe() const {
  return fmt::format("fmu: {} ({}, FMI {})", binding_->fmu, binding_->md.model_name,
                     binding_->md.fmi_version);
}

nlohmann::json FmuSubstructure::SaveState() const {
  nlohmann::json state = {{"t", t_committed_}};
  if (!binding_->stateless && binding_->md.can_serialize_state) {
    state["fmu_state"] = ToHex(fmu_->SerializeSnapshot());
  }
  return state;
}

void FmuSubstructure::RestoreState(const nlohmann::json& state) {
  if (!state.is_object() || !state.contains("t") || !state["t"].is_number()) {
    throw Error(fmt::format("{}: the saved state is not an FMU substructure's", binding_->fmu));
  }
  const double t = state["t"].get<double>();
  if (binding_->stateless) {
    if (t > t_committed_) fmu_->DoStep(t_committed_, t - t_committed_);  // its time only
  } else {
    if (!state.contains("fmu_state")) {
      throw Error(fmt::format(
          "{}: cannot resume: the FMU keeps a state but cannot serialize it "
          "(canSerializeFMUstate is false), so the checkpoint holds no FMU state; run again "
          "from the start, or export the FMU with state serialization", binding_->fmu));
    }
    fmu_->DeserializeIntoSnapshot(FromHex(state["fmu_state"].get<std::string>()));
    fmu_->RestoreSnapshot();
  }
  t_committed_ = t;
  t_trial_ = t;
  moved_ = false;
}

}  // namespace hybridtest::fmi
