// AdsTransfer::Execute and Probe (ads_transfer.h): one sum write of the commands and their
// sequence, sum reads until the PLC acknowledges it, the checks of what came back.
#include <fmt/core.h>

#include <cmath>
#include <thread>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/ads/ads_transfer.h"
#include "hybridtest/transfer/safety.h"

namespace hybridtest::transfer::ads {
namespace {

using Clock = std::chrono::steady_clock;

// "1.5" for one value, "[1.5, 2]" for several.
std::string List(std::span<const double> values) {
  std::string text;
  for (double v : values) text += (text.empty() ? "" : ", ") + fmt::format("{}", v);
  return values.size() == 1 ? text : "[" + text + "]";
}

}  // namespace

void AdsTransfer::Execute(std::span<const double> commands, std::span<Measurement> out) {
  const AdsProfile& p = options_.profile;
  const auto n = static_cast<std::size_t>(p.actuators);
  const std::string& unit = p.units.length_name;
  if (commands.size() != n || out.size() != n) {
    throw TransferError(fmt::format("{}: {} commands for {} actuators: nothing was sent",
                                    Describe(), commands.size(), n));
  }
  const std::string sent = fmt::format("command{} {} {}", n > 1 ? "s" : "", List(commands), unit);
  if (!active_ || !link_.is_open()) {
    throw TransferError(fmt::format("{} is not active (not activated, holding, or the "
                                    "connection was lost): {} not sent; call Activate() first",
                                    Subject(), sent));
  }
  if (!read_failure_.empty()) {
    throw TransferError(fmt::format(
        "{} not sent: the actuators' positions could not be read before moving ({}); "
        "hybridtest does not move an actuator it cannot see. Check the link and the PLC, then "
        "start again (Activate; `hybridtest resume` again)", sent, read_failure_));
  }
  const std::uint32_t sequence = last_ack_ + 1;  // modulo 2^32, as a UDINT
  const std::string waiting = fmt::format("while waiting for the ack of {} ({} = {})", sent,
                                          p.symbols[kSequence], sequence);
  // 1. The commands, then their sequence, in one sum write (the PLC takes the command when
  // the sequence changes, after the array is in place).
  try {
    const Role roles[] = {kCommand, kSequence, kHeartbeat};
    const std::vector<std::uint8_t> values[] = {EncodeReals(commands), EncodeUdint(sequence),
                                                NextHeartbeat()};
    WriteSymbols(roles, values, options_.response_timeout,
                 fmt::format("{} with {} = {}", sent, p.symbols[kSequence], sequence));
  } catch (const AdsError& e) {
    HoldAndFail(fmt::format("{}; {} was set", e.what(), p.symbols[kHold]));
  }
  // 2. Read until the PLC acknowledges the sequence.
  const auto deadline = Clock::now() + std::chrono::duration<double>(options_.ack_timeout);
  Readout r;
  for (;;) {
    try {
      r = ReadOutputs(waiting);
    } catch (const AdsError& e) {
      HoldAndFail(fmt::format("{}; {} was set", e.what(), p.symbols[kHold]));
    }
    CheckFault(r, waiting);
    if (!r.enabled) {
      HoldAndFail(fmt::format("{} dropped the enable ({} = FALSE) {}: {}; {} was set", Subject(),
                              p.symbols[kEnabled], waiting, Describe(r), p.symbols[kHold]));
    }
    if (r.holding) {
      HoldAndFail(fmt::format("{} reports holding ({} = TRUE) {}: {}; it holds on its own (an "
                              "operator, an interlock or its watchdog) and the test stops. Find "
                              "out why it holds, then `hybridtest resume`", Subject(),
                              p.symbols[kHolding], waiting, Describe(r)));
    }
    if (r.ack == sequence) break;
    if (r.ack != last_ack_) {
      HoldAndFail(fmt::format("{} acknowledged {} = {}, expected {} (or the previous {} while "
                              "moving) {}: {}; is another client writing to it? {} was set",
                              Subject(), p.symbols[kAck], r.ack, sequence, last_ack_, waiting,
                              Describe(r), p.symbols[kHold]));
    }
    if (Clock::now() >= deadline) {
      HoldAndFail(fmt::format("{} did not acknowledge within {} s {}: last read {}; {} was set",
                              Subject(), options_.ack_timeout, waiting, Describe(r),
                              p.symbols[kHold]));
    }
    BeatWhileWaiting();  // the PLC's watchdog sees hybridtest wait
    if (options_.poll_interval > 0.0) {
      std::this_thread::sleep_for(std::chrono::duration<double>(options_.poll_interval));
    }
  }
  last_ack_ = sequence;
  // 3. The first exchange must be plausible (a wrong unit or variable shows here).
  for (std::size_t k = 0; k < n && first_exchange_; ++k) {
    const bool position_ok = std::abs(r.position[k] - commands[k]) <= *options_.position_tolerance;
    const bool force_ok = std::abs(r.force[k]) <= *options_.force_plausible;  // false for NaN
    if (!position_ok || !force_ok) {
      HoldAndFail(fmt::format(
          "implausible first measurement of actuator {} from {}: command {} {}, {}; expected the "
          "position within {} {} of the command and |force| ≤ {} {}; check transfer.units and "
          "the PLC's scaling of {} and {}", k + 1, Subject(), commands[k], unit, Describe(r),
          *options_.position_tolerance, unit, *options_.force_plausible, p.units.force_name,
          p.symbols[kPosition], p.symbols[kForce]));
    }
  }
  // 4. Every exchange: the settled actuator is where it was sent, and the reading answers this
  // command (safety_settled_reading.h).
  SettledReadingCheck::Source source;
  source.unit = unit;
  source.metres_per_unit = p.units.metres_per_length_unit;
  source.answered = [&](std::size_t k) {
    return fmt::format("The PLC at {} (actuator {}) acknowledged command {} {} ({} = {})",
                       link_.Where(), k + 1, commands[k], unit, p.symbols[kSequence], sequence);
  };
  source.detail = [&](std::size_t) { return " (" + Describe(r) + ")"; };
  source.after = p.symbols[kHold] + " was set";
  source.following_key = "transfer.following_error";
  source.settle_key = "transfer.settle_tolerance";
  try {
    settled_.Check(commands, r.position, source);
  } catch (const SafetyStop&) {
    Hold();
    throw;
  }
  first_exchange_ = false;
  const double lab_time = WallSinceActivate();
  for (std::size_t k = 0; k < n; ++k) out[k] = Measurement{r.position[k], r.force[k], lab_time};
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
    reading.status += fmt::format("; positions {} {}, forces {} {}", List(r.position),
                                  p.units.length_name, List(r.force), p.units.force_name);
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
