#pragma once
// SlotLaw: an emulated specimen's restoring-force law as the model's slot sees it through the
// setup of one actuator and one slot (actuator_setup.h) and the bench (bench_config.h),
// noise-free — what a numerical reference of a hybrid test must use for a physical slot
// (`plan`, docs/lab-time.md):
//
//   command       c = a(d)                  [m]   (the setup; p0 + sign · scale · d for
//                                                  `setup: {p0, sign, scale, ...}`)
//   deformation   δ = c − p0_bench          [m]   (the bench's zero-force position)
//   force         F = law(δ) + offset_bench [N]   (the load cell, without noise)
//   slot force    r = J(d)ᵀ (F − load_cell_zero)   (force_sign · force_scale · (F − zero))
//
// so dr/dd = setup.SlotStiffness(dlaw/dδ) (initial_stiffness();
// force_sign · force_scale · sign · scale · dlaw/dδ for the one-actuator setup). Trial and
// Commit go to the wrapped law, so a hysteretic specimen keeps its path. Bench units cancel (the
// setup converts to them and back). What it leaves out: the actuator's path between targets
// (overshoot: actuator.approach), settling and load-cell noise.
#include <memory>

#include "hybridtest/constitutive/restoring_force_law.h"
#include "hybridtest/substructures/actuator_setup.h"
#include "hybridtest/substructures/setup_transform.h"
#include "hybridtest/substructures/substructure.h"
#include "hybridtest/transfer/bench_spec.h"

namespace hybridtest::substructures {

class SlotLaw final : public constitutive::RestoringForceLaw {
 public:
  // bench_p0 [m], bench_offset [N]: the emulated bench's zero-force position and load-cell
  // offset.
  // Throws ConfigError unless the setup has one actuator and one slot.
  SlotLaw(std::unique_ptr<constitutive::RestoringForceLaw> specimen,
          std::shared_ptr<const ActuatorSetup> setup, double bench_p0, double bench_offset);

  double Trial(double displacement) override;
  void Commit() override { specimen_->Commit(); }
  double initial_stiffness() const override;
  std::unique_ptr<constitutive::RestoringForceLaw> Clone() const override;
  std::string Describe() const override;
  nlohmann::json SaveState() const override { return specimen_->SaveState(); }
  void RestoreState(const nlohmann::json& state) override { specimen_->RestoreState(state); }

 private:
  std::unique_ptr<constitutive::RestoringForceLaw> specimen_;
  std::shared_ptr<const ActuatorSetup> setup_;
  double bench_p0_, bench_offset_;
  Eigen::VectorXd d_, a_, f_, r_;  // (1) each
};

// The configuration of an in-process emulated bench of one actuator in its one-actuator form
// (its scalar specimen law), or nullptr for any other transfer system.
const transfer::EmulatedBenchConfig* OneActuatorBench(const transfer::TransferSystem* transfer);
// The spec of an in-process emulated bench in its coupled `actuators:` form (n ≥ 1 actuators,
// one specimen law in actuator coordinates), or nullptr for any other transfer system.
const transfer::EmulatedBenchSpec* CoupledBench(const transfer::TransferSystem* transfer);

// The law at the slot of a physical substructure of one actuator and one slot on an in-process
// emulated bench (a copy of the configured specimen, virgin: the state a run starts from);
// nullptr for any other substructure or transfer system.
std::unique_ptr<constitutive::RestoringForceLaw> EmulatedSlotLaw(const Substructure& substructure);

}  // namespace hybridtest::substructures
