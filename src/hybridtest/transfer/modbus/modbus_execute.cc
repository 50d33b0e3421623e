// ModbusTransfer::Execute (modbus_transfer.h): write every actuator's command and sequence,
// poll until every actuator acknowledges its own, check what came back.
#include <errno.h>
#include <fmt/core.h>
#include <modbus.h>

#include <cmath>
#include <thread>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/modbus/modbus_transfer.h"
#include "hybridtest/transfer/safety.h"

namespace hybridtest::transfer::modbus {
namespace {

using Clock = std::chrono::steady_clock;

// "1.5" for one value, "[1.5, 2]" for several.
template <class T>
std::string List(std::span<const T> values) {
  if (values.size() == 1) return fmt::format("{}", values[0]);
  std::string text = "[";
  for (std::size_t k = 0; k < values.size(); ++k) {
    text += fmt::format("{}{}", k == 0 ? "" : ", ", values[k]);
  }
  return text + "]";
}

}  // namespace

void ModbusTransfer::Execute(std::span<const double> commands, std::span<Measurement> out) {
  const std::size_t n = maps_.size();
  const std::string& unit = maps_[0].units.length_name;
  if (commands.size() != n || out.size() != n) {
    throw TransferError(fmt::format("{}: {} commands for {} actuators: nothing was sent",
                                    Describe(), commands.size(), n));
  }
  const bool several = n > 1;
  const std::string held = several ? "every actuator's hold coil was set" : "the hold coil was set";
  const std::string sent = fmt::format("command{} {} {}", several ? "s" : "", List(commands), unit);
  if (!active_ || ctx_ == nullptr) {
    throw TransferError(fmt::format(
        "the Modbus controller at {} is not active (not activated, holding, or the connection "
        "was lost): {} not sent; call Activate() first", Endpoint(), sent));
  }
  if (!read_failure_.empty()) {
    throw TransferError(fmt::format(
        "{} not sent: the actuator's position could not be read before moving ({}); "
        "hybridtest does not move an actuator it cannot see. Check the link and the controller, "
        "then start again (Activate; `hybridtest resume` again)", sent, read_failure_));
  }
  std::vector<std::uint64_t> sequence(n);
  for (std::size_t k = 0; k < n; ++k) sequence[k] = (last_ack_[k] + 1) % maps_[k].sequence_modulus();
  const std::string sequences = List<std::uint64_t>(sequence);
  // 1. Every command with its sequence (function 16): one write per run of adjacent blocks,
  // every one encoded first (a command its type cannot hold is refused before any is sent).
  std::vector<std::vector<std::uint16_t>> encoded;
  for (const WriteBlock& w : writes_) {
    std::vector<std::uint16_t>& words = encoded.emplace_back(static_cast<std::size_t>(w.block.count));
    for (int a : w.actuators) {
      const auto k = static_cast<std::size_t>(a);
      const RegisterMap& m = maps_[k];
      EncodeValue(m, m.command, commands[k], words.data() + (m.command.address - w.block.start));
      EncodeValue(m, m.sequence, static_cast<double>(sequence[k]),
                  words.data() + (m.sequence.address - w.block.start));
    }
  }
  for (std::size_t i = 0; i < writes_.size(); ++i) {
    const WriteBlock& w = writes_[i];
    ++requests_;
    if (modbus_write_registers(ctx_, w.block.start, w.block.count, encoded[i].data()) !=
        w.block.count) {
      const int error = errno;
      if (i > 0) HoldIfSeveral();  // an earlier write went through: that actuator moves
      std::vector<double> these;
      std::vector<std::uint64_t> their;
      for (int a : w.actuators) {
        these.push_back(commands[static_cast<std::size_t>(a)]);
        their.push_back(sequence[static_cast<std::size_t>(a)]);
      }
      std::vector<int> numbers;
      for (int a : w.actuators) numbers.push_back(a + 1);
      const std::string whose = several ? fmt::format("actuator{} {} ",
                                                      numbers.size() > 1 ? "s" : "",
                                                      List<int>(numbers))
                                        : "";
      FailRequest(fmt::format("to accept {}command {} {} with sequence {} (write of holding "
                              "registers {}–{})", whose, List<double>(these), unit,
                              List<std::uint64_t>(their), w.block.start,
                              w.block.start + w.block.count - 1), error);
    }
  }
  // 2. Poll until every actuator acknowledges its own sequence.
  const std::string waiting =
      several ? fmt::format("while waiting for the acks of commands {} {} (sequences {})",
                            List(commands), unit, sequences)
              : fmt::format("while waiting for the ack of command {} {} (sequence {})",
                            commands[0], unit, sequence[0]);
  const auto deadline = Clock::now() + std::chrono::duration<double>(options_.ack_timeout);
  std::vector<Readout> r;
  for (;;) {
    r = ReadRegisters(waiting);
    CheckFault(r, waiting);
    bool acked = true;
    for (std::size_t k = 0; k < n; ++k) {
      const StatusBits& b = maps_[k].status_bits;
      if (maps_[k].status && b.enabled >= 0 && !Bit(r[k], b.enabled)) {
        HoldIfSeveral();
        Fail(fmt::format("{} dropped the enable (status bit {}) {}: {}{}", Subject(k), b.enabled,
                         waiting, Describe(r[k], k), several ? "; " + held : ""), false);
      }
      if (Bit(r[k], b.holding)) {
        HoldIfSeveral();
        Fail(fmt::format("{} reports holding (status bit {}) {}: {}; it holds on its own (an "
                         "operator, an interlock or its watchdog) and the test stops{}. Find out "
                         "why it holds, then `hybridtest resume`", Subject(k), b.holding, waiting,
                         Describe(r[k], k), several ? "; " + held : ""), false);
      }
      acked = acked && r[k].ack == sequence[k];
    }
    if (acked) break;
    // The link works but the controller does not do what it should: hold, then stop.
    for (std::size_t k = 0; k < n; ++k) {
      if (r[k].ack == sequence[k] || r[k].ack == last_ack_[k]) continue;
      Hold();
      Fail(fmt::format("{} acknowledged sequence {}, expected {} (or the previous {} while "
                       "moving) {}: {}; is another client writing to it? {}{}", Subject(k),
                       r[k].ack, sequence[k], last_ack_[k], waiting, Describe(r[k], k),
                       several ? "E" : "T", held.substr(1)), false);
    }
    if (Clock::now() >= deadline) {
      std::size_t k = 0;
      while (r[k].ack == sequence[k]) ++k;
      Hold();
      Fail(fmt::format("{} did not acknowledge within {} s {}: last read {}; {}", Subject(k),
                       options_.ack_timeout, waiting, Describe(r[k], k), held), false);
    }
    if (options_.poll_interval > 0.0) {
      std::this_thread::sleep_for(std::chrono::duration<double>(options_.poll_interval));
    }
  }
  last_ack_ = sequence;
  const std::string& force_unit = maps_[0].units.force_name;
  for (std::size_t k = 0; k < n; ++k) {
    // 3. The first exchange must be plausible (catches a wrong word or byte order).
    if (first_exchange_) {
      const bool position_ok = std::abs(r[k].position - commands[k]) <= *options_.position_tolerance;
      const bool force_ok = std::abs(r[k].force) <= *options_.force_plausible;  // false for NaN
      if (!position_ok || !force_ok) {
        HoldIfSeveral();
        Fail(fmt::format("implausible first measurement from {}: command {} {}, {}; expected the "
                         "position within {} {} of the command and |force| ≤ {} {}; check the "
                         "map (type, word_order, byte_order, scale, units) against the "
                         "controller's manual", Subject(k), commands[k], unit, Describe(r[k], k),
                         *options_.position_tolerance, unit, *options_.force_plausible,
                         force_unit), false);
      }
    }
  }
  // 4. Every exchange: the settled actuator must be where it was sent, and the reading must be
  // the answer to this command, not the previous one (safety_settled_reading.h).
  std::vector<double> positions(n);
  for (std::size_t k = 0; k < n; ++k) positions[k] = r[k].position;
  SettledReadingCheck::Source source;
  source.unit = unit;
  source.metres_per_unit = maps_[0].units.metres_per_length_unit;
  source.answered = [&](std::size_t k) {
    return fmt::format("T{} acknowledged command {} {} (sequence {})", Subject(k).substr(1),
                       commands[k], unit, sequence[k]);
  };
  source.detail = [&](std::size_t k) { return " (" + Describe(r[k], k) + ")"; };
  source.after = held;
  source.following_key = "transfer.following_error";
  source.settle_key = "transfer.settle_tolerance";
  try {
    settled_.Check(commands, positions, source);
  } catch (const SafetyStop&) {
    Hold();
    throw;
  }
  first_exchange_ = false;
  const double lab_time =
      maps_[0].lab_time ? r[0].lab_time - lab_time_origin_ : WallSinceActivate();
  for (std::size_t k = 0; k < n; ++k) out[k] = Measurement{r[k].position, r[k].force, lab_time};
}

}  // namespace hybridtest::transfer::modbus
