// PhysicalSubstructure: the two phases of a trial (substructure.h; docs/multi-site.md).
#include <fmt/core.h>

#include "hybridtest/common/error.h"
#include "hybridtest/substructures/physical_substructure.h"

namespace hybridtest::substructures {

void PhysicalSubstructure::Propose(std::span<const double> d, const TrialContext& ctx) {
  const Eigen::Map<const Eigen::VectorXd> dv(d.data(), static_cast<Eigen::Index>(d.size()));
  CheckSlotDisplacements(d, ctx);
  try {
    setup_->CalcCommands(dv, Eigen::Map<Eigen::VectorXd>(commands_.data(), num_actuators()));
  } catch (const Error& e) {
    throw Error(fmt::format("{}: {} (step {}, stage {}, t = {} s; nothing moved)", name_,
                            e.what(), ctx.step, ctx.stage, ctx.t));
  }
  // The gate's command checks, as Trial's move will make them, without moving.
  gate_.Vet(commands_, {ctx.step, ctx.stage});
  // In the bench's unit, computed as the gate computes what Execute is given.
  const double metres = transfer_->bench_units().metres_per_length_unit;
  proposed_.resize(commands_.size());
  for (std::size_t k = 0; k < commands_.size(); ++k) proposed_[k] = commands_[k] / metres;
  try {
    transfer_->Propose(proposed_, ctx.step, ctx.stage);
  } catch (const TransferError& e) {
    throw TransferError(fmt::format("{}: {} (step {}, stage {}; nothing moved)", name_, e.what(),
                                    ctx.step, ctx.stage));
  }
}

void PhysicalSubstructure::AwaitVerdict() {
  try {
    transfer_->AwaitVerdict();
  } catch (const TransferError& e) {
    throw TransferError(fmt::format("{}: {} (nothing moved)", name_, e.what()));
  }
}

void PhysicalSubstructure::Release() { transfer_->Release(); }

}  // namespace hybridtest::substructures
