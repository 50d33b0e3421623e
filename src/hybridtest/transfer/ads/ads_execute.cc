// AdsTransfer::Execute and Probe (ads_transfer.h): the acknowledged move (acknowledged_move.h)
// over the profile's symbols — one sum write of the commands and their sequence, sum reads of
// the outputs, bHold, the heartbeat while waiting, and the symbol names in its messages.
#include <fmt/core.h>

#include <cmath>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/acknowledged_move.h"
#include "hybridtest/transfer/ads/ads_transfer.h"

namespace hybridtest::transfer::ads {

class AdsTransfer::Controller final : public AckController {
 public:
  explicit Controller(AdsTransfer& t) : t_(t), p_(t.options_.profile) {}

  // The commands, then their sequence, in one sum write (the PLC takes the command when the
  // sequence changes, after the array is in place).
  void Write(std::span<const double> commands,
             std::span<const std::uint64_t> sequence) override {
    const auto s = static_cast<std::uint32_t>(sequence[0]);
    const Role roles[] = {kCommand, kSequence, kHeartbeat};
    const std::vector<std::uint8_t> values[] = {EncodeReals(commands), EncodeUdint(s),
                                                t_.NextHeartbeat()};
    Named([&] {
      t_.WriteSymbols(roles, values, t_.options_.response_timeout,
                      fmt::format("command{} {} {} with {} = {}", commands.size() > 1 ? "s" : "",
                                  ValueList(commands), p_.units.length_name,
                                  p_.symbols[kSequence], s));
    });
  }

  void Read(std::vector<AckReading>& out, const std::string& why) override {
    Named([&] { raw_ = t_.ReadOutputs(why); });
    out.resize(raw_.position.size());
    for (std::size_t k = 0; k < out.size(); ++k) {
      out[k] = AckReading{raw_.position[k], raw_.force[k], raw_.ack, raw_.fault, raw_.enabled,
                          raw_.holding};
    }
  }

  void Wait() override {
    Named([&] { t_.BeatIfDue(); });  // the PLC's watchdog sees hybridtest wait
  }

  void Hold() noexcept override { t_.Hold(); }

  std::string Name() const override { return t_.Subject(); }
  std::string Subject(std::size_t k) const override {
    return p_.actuators == 1 ? t_.Subject() : fmt::format("{} (actuator {})", t_.Subject(), k + 1);
  }
  std::string Describe(std::size_t) const override { return t_.Describe(raw_); }
  std::string Where(Flag flag, std::size_t) const override {
    if (flag == Flag::kFault) return p_.symbols[kFault] + " = TRUE";
    if (flag == Flag::kEnabled) return p_.symbols[kEnabled] + " = FALSE";
    return p_.symbols[kHolding] + " = TRUE";
  }
  std::string Sequences(std::span<const std::uint64_t> sequences) const override {
    return fmt::format("{} = {}", p_.symbols[kSequence], sequences[0]);
  }
  std::string Ack(std::size_t, std::uint64_t ack) const override {
    return fmt::format("{} = {}", p_.symbols[kAck], ack);
  }
  std::string Held() const override {
    return p_.symbols[kHold] + " was set (every actuator holds)";
  }
  std::string PlausibilityHint() const override {
    return fmt::format("check transfer.units and the PLC's scaling of {} and {}",
                       p_.symbols[kPosition], p_.symbols[kForce]);
  }

 private:
  // An ADS error code in an answer (the link still works, so the hold reaches the PLC): the
  // message says so; the move holds.
  template <class F>
  void Named(F&& request) {
    try {
      request();
    } catch (const AdsError& e) {
      throw TransferError(fmt::format("{}; {} was set", e.what(), p_.symbols[kHold]));
    }
  }

  AdsTransfer& t_;
  const AdsProfile& p_;
  Readout raw_;
};

void AdsTransfer::Execute(std::span<const double> commands, std::span<Measurement> out) {
  Controller io(*this);
  move_.Move(commands, out, io, active_ && link_.is_open(), read_failure_);
  const double lab_time = WallSinceActivate();
  for (Measurement& m : out) m.lab_time = lab_time;
}

std::optional<ProbeReading> AdsTransfer::Probe() {
  if (!link_.is_open()) Connect();
  const AdsProfile& p = options_.profile;
  const Readout r = ReadOutputs("the probe, before anything moves");
  ProbeReading reading;
  for (std::size_t k = 0; k < r.position.size(); ++k) {
    reading.measurements.push_back(Measurement{r.position[k], r.force[k], 0.0});
  }
  reading.status = fmt::format("PLC in RUN, every symbol of the profile present; {}, {}, {}",
                               r.fault ? "FAULT" : "no fault",
                               r.enabled ? "enabled" : "not enabled",
                               r.holding ? "holding" : "not holding");
  if (p.actuators > 1) {
    reading.status += fmt::format("; positions {} {}, forces {} {}",
                                  ValueList<double>(r.position),
                                  p.units.length_name, ValueList<double>(r.force),
                                  p.units.force_name);
  }
  if (r.fault) {
    reading.problem = fmt::format("the PLC reports a fault ({} = TRUE): clear it at the PLC "
                                  "first", p.symbols[kFault]);
  }
  for (std::size_t k = 0; k < r.position.size() && reading.problem.empty(); ++k) {
    if (!std::isfinite(r.position[k]) || !std::isfinite(r.force[k])) {
      reading.problem = fmt::format("actuator {}: position or force is not a number ({})", k + 1,
                                    Describe(r));
    }
  }
  return reading;
}

}  // namespace hybridtest::transfer::ads
