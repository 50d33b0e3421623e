// See safety_gate.h.
#include "hybridtest/transfer/safety_gate.h"

namespace hybridtest::transfer {

void SafetyGate::Move(TransferSystem& transfer, double command_m, MoveLabel label,
                      double load_cell_zero, GatedMove& out,
                      const std::function<void()>& before_execute) {
  const BenchUnits units = transfer.bench_units();
  Execute(transfer, units, command_m, command_m / units.metres_per_length_unit, label,
          load_cell_zero, out, before_execute);
}

void SafetyGate::MoveBench(TransferSystem& transfer, double command_bench, MoveLabel label,
                           GatedMove& out, const std::function<void()>& before_execute) {
  const BenchUnits units = transfer.bench_units();
  Execute(transfer, units, command_bench * units.metres_per_length_unit, command_bench, label, 0.0,
          out, before_execute);
}

void SafetyGate::Execute(TransferSystem& transfer, const BenchUnits& units, double command_m,
                         double command_bench, MoveLabel label, double load_cell_zero,
                         GatedMove& out, const std::function<void()>& before_execute) {
  out.executed = false;
  out.command = command_m;
  monitor_.CheckCommand(command_m, label.step, label.stage);
  if (before_execute) before_execute();
  const Measurement m = transfer.Execute(command_bench);
  out.raw = m;
  out.position = m.position * units.metres_per_length_unit;
  out.force = m.force * units.newtons_per_force_unit - load_cell_zero;
  out.lab_time = m.lab_time;
  out.executed = true;
  monitor_.CheckMeasurement(command_m, out.position, out.force, label.step, label.stage);
}

}  // namespace hybridtest::transfer
