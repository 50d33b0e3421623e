#include "hybridtest/transfer/numerical_loopback.h"

#include <fmt/format.h>

#include "hybridtest/common/error.h"

namespace hybridtest::transfer {

NumericalLoopback::NumericalLoopback(std::unique_ptr<constitutive::RestoringForceLaw> law,
                                     double p0)
    : law_(std::move(law)), p0_(p0) {
  if (!law_) throw ConfigError("numerical loopback: no restoring-force law given");
}

void NumericalLoopback::Execute(std::span<const double> commands, std::span<Measurement> out) {
  RequireOneActuator(commands, out, "numerical loopback");
  const double command = commands[0];
  if (!active_) {
    throw TransferError(fmt::format("numerical loopback: Execute({} m) while not active; call "
                                    "Activate() first (also to resume after a hold)",
                                    command));
  }
  const double force = law_->Trial(command - p0_);
  law_->Commit();
  out[0] = Measurement{command, force, 0.0};
}

std::string NumericalLoopback::Describe() const {
  return fmt::format("numerical loopback ({}; p0={:g} m)", law_->Describe(), p0_);
}

}  // namespace hybridtest::transfer
