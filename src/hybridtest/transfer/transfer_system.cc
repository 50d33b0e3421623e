// See transfer_system.h.
#include "hybridtest/transfer/transfer_system.h"

#include <fmt/format.h>

namespace hybridtest::transfer {

Measurement ExecuteOne(TransferSystem& transfer, double command) {
  if (transfer.num_actuators() != 1) {
    throw TransferError(fmt::format(
        "{}: one command for {} actuators; send one command per actuator (a substructure with "
        "`setup: transform` does)", transfer.Describe(), transfer.num_actuators()));
  }
  Measurement m;
  transfer.Execute(std::span<const double>(&command, 1), std::span<Measurement>(&m, 1));
  return m;
}

std::optional<Measurement> ReadOne(TransferSystem& transfer) {
  if (transfer.num_actuators() != 1) return std::nullopt;
  std::optional<std::vector<Measurement>> all = transfer.ReadAll();
  if (!all || all->size() != 1) return std::nullopt;
  return (*all)[0];
}

void RequireOneActuator(std::span<const double> commands, std::span<const Measurement> out,
                        std::string_view who) {
  if (commands.size() != 1 || out.size() != 1) {
    throw TransferError(fmt::format("{}: {} commands and {} measurements for its one actuator",
                                    who, commands.size(), out.size()));
  }
}

}  // namespace hybridtest::transfer
