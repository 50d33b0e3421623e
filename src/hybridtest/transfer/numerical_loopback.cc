#include "hybridtest/transfer/numerical_loopback.h"

#include <fmt/format.h>

#include "hybridtest/common/error.h"

namespace hybridtest::transfer {

namespace {

std::vector<std::unique_ptr<constitutive::RestoringForceLaw>> One(
    std::unique_ptr<constitutive::RestoringForceLaw> law) {
  std::vector<std::unique_ptr<constitutive::RestoringForceLaw>> laws;
  laws.push_back(std::move(law));
  return laws;
}

}  // namespace

NumericalLoopback::NumericalLoopback(std::unique_ptr<constitutive::RestoringForceLaw> law,
                                     double p0)
    : NumericalLoopback(One(std::move(law)), std::vector<double>{p0}) {}

NumericalLoopback::NumericalLoopback(
    std::vector<std::unique_ptr<constitutive::RestoringForceLaw>> laws, std::vector<double> p0)
    : laws_(std::move(laws)), p0_(std::move(p0)) {
  if (laws_.empty()) throw ConfigError("numerical loopback: no restoring-force law given");
  if (p0_.size() != laws_.size()) {
    throw ConfigError(fmt::format("numerical loopback: {} laws and {} zero-force positions p0: "
                                  "give one p0 per actuator", laws_.size(), p0_.size()));
  }
  for (std::size_t k = 0; k < laws_.size(); ++k) {
    if (!laws_[k]) {
      throw ConfigError(laws_.size() == 1
                            ? std::string("numerical loopback: no restoring-force law given")
                            : fmt::format("numerical loopback: actuator {}: no restoring-force "
                                          "law given", k));
    }
  }
}

void NumericalLoopback::Execute(std::span<const double> commands, std::span<Measurement> out) {
  if (commands.size() != laws_.size() || out.size() != laws_.size()) {
    throw TransferError(fmt::format("numerical loopback: {} commands and {} measurements for "
                                    "its {} actuator(s)", commands.size(), out.size(),
                                    laws_.size()));
  }
  if (!active_) {
    throw TransferError(fmt::format("numerical loopback: Execute({} m) while not active; call "
                                    "Activate() first (also to resume after a hold)",
                                    commands[0]));
  }
  for (std::size_t k = 0; k < laws_.size(); ++k) {
    const double force = laws_[k]->Trial(commands[k] - p0_[k]);
    laws_[k]->Commit();
    out[k] = Measurement{commands[k], force, 0.0};
  }
}

std::string NumericalLoopback::Describe() const {
  if (laws_.size() == 1) {
    return fmt::format("numerical loopback ({}; p0={:g} m)", laws_[0]->Describe(), p0_[0]);
  }
  std::string laws;
  for (std::size_t k = 0; k < laws_.size(); ++k) {
    laws += fmt::format("{}{}; p0={:g} m", k > 0 ? " | " : "", laws_[k]->Describe(), p0_[k]);
  }
  return fmt::format("numerical loopback of {} actuators ({})", laws_.size(), laws);
}

}  // namespace hybridtest::transfer
