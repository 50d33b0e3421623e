// ModbusTransfer::Execute (modbus_transfer.h): the acknowledged move (acknowledged_move.h) over
// the register map — the writes of every actuator's command and sequence, the reads of the
// readout registers, the hold coils, and the names of registers and bits in its messages.
#include <errno.h>
#include <fmt/core.h>
#include <modbus.h>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/acknowledged_move.h"
#include "hybridtest/transfer/modbus/modbus_transfer.h"

namespace hybridtest::transfer::modbus {

class ModbusTransfer::Controller final : public AckController {
 public:
  explicit Controller(ModbusTransfer& t) : t_(t) {}

  // Function 16: one write per run of adjacent blocks, every one encoded first (a command its
  // type cannot hold is refused before any is sent).
  void Write(std::span<const double> commands,
             std::span<const std::uint64_t> sequence) override {
    const std::vector<RegisterMap>& maps = t_.maps_;
    std::vector<std::vector<std::uint16_t>> encoded;
    for (const WriteBlock& w : t_.writes_) {
      std::vector<std::uint16_t>& words =
          encoded.emplace_back(static_cast<std::size_t>(w.block.count));
      for (int a : w.actuators) {
        const auto k = static_cast<std::size_t>(a);
        const RegisterMap& m = maps[k];
        EncodeValue(m, m.command, commands[k], words.data() + (m.command.address - w.block.start));
        EncodeValue(m, m.sequence, static_cast<double>(sequence[k]),
                    words.data() + (m.sequence.address - w.block.start));
      }
    }
    for (std::size_t i = 0; i < t_.writes_.size(); ++i) {
      const WriteBlock& w = t_.writes_[i];
      ++t_.requests_;
      if (modbus_write_registers(t_.ctx_, w.block.start, w.block.count, encoded[i].data()) ==
          w.block.count) {
        continue;
      }
      const int error = errno;
      std::vector<double> these;
      std::vector<std::uint64_t> their;
      std::vector<int> numbers;
      for (int a : w.actuators) {
        these.push_back(commands[static_cast<std::size_t>(a)]);
        their.push_back(sequence[static_cast<std::size_t>(a)]);
        numbers.push_back(a + 1);
      }
      const std::string whose =
          maps.size() > 1 ? fmt::format("actuator{} {} ", numbers.size() > 1 ? "s" : "",
                                        ValueList<int>(numbers))
                          : "";
      t_.FailRequest(fmt::format("to accept {}command {} {} with sequence {} (write of holding "
                                 "registers {}–{})", whose, ValueList<double>(these),
                                 maps[0].units.length_name, ValueList<std::uint64_t>(their),
                                 w.block.start, w.block.start + w.block.count - 1), error);
    }
  }

  void Read(std::vector<AckReading>& out, const std::string& why) override {
    raw_ = t_.ReadRegisters(why);
    out.resize(raw_.size());
    for (std::size_t k = 0; k < raw_.size(); ++k) {
      const Readout& r = raw_[k];
      const RegisterMap& m = t_.maps_[k];
      const StatusBits& b = m.status_bits;
      out[k].position = r.position;
      out[k].force = r.force;
      out[k].ack = r.ack;
      out[k].fault = Bit(r, b.fault);
      out[k].enabled = !m.status || b.enabled < 0 || Bit(r, b.enabled);
      out[k].holding = Bit(r, b.holding);
    }
  }

  void Hold() noexcept override { t_.Hold(); }

  std::string Name() const override { return "the Modbus controller at " + t_.Endpoint(); }
  std::string Subject(std::size_t k) const override { return t_.Subject(k); }
  std::string Describe(std::size_t k) const override { return t_.Describe(raw_[k], k); }
  std::string Where(Flag flag, std::size_t k) const override {
    const StatusBits& b = t_.maps_[k].status_bits;
    return fmt::format("status bit {}", flag == Flag::kFault     ? b.fault
                                        : flag == Flag::kEnabled ? b.enabled
                                                                 : b.holding);
  }
  std::string Sequences(std::span<const std::uint64_t> sequences) const override {
    return fmt::format("sequence{} {}", sequences.size() > 1 ? "s" : "", ValueList(sequences));
  }
  std::string Ack(std::size_t, std::uint64_t ack) const override {
    return fmt::format("sequence {}", ack);
  }
  std::string Held() const override {
    return t_.maps_.size() > 1 ? "every actuator's hold coil was set" : "the hold coil was set";
  }
  std::string PlausibilityHint() const override {
    return "check the map (type, word_order, byte_order, scale, units) against the "
           "controller's manual";
  }

  // The registers of the read that carried the acks.
  const std::vector<Readout>& raw() const { return raw_; }

 private:
  ModbusTransfer& t_;
  std::vector<Readout> raw_;
};

void ModbusTransfer::Execute(std::span<const double> commands, std::span<Measurement> out) {
  Controller io(*this);
  move_.Move(commands, out, io, active_ && ctx_ != nullptr, read_failure_);
  const double lab_time =
      maps_[0].lab_time ? io.raw()[0].lab_time - lab_time_origin_ : WallSinceActivate();
  for (Measurement& m : out) m.lab_time = lab_time;
}

}  // namespace hybridtest::transfer::modbus
