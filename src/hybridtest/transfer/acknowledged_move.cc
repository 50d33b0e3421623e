// See acknowledged_move.h.
#include "hybridtest/transfer/acknowledged_move.h"

#include <fmt/core.h>

#include <chrono>
#include <cmath>
#include <thread>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/safety.h"

namespace hybridtest::transfer {
namespace {

using AckClock = std::chrono::steady_clock;

// "The hold coil was set" from "the hold coil was set".
std::string Capitalised(std::string text) {
  if (!text.empty() && text[0] >= 'a' && text[0] <= 'z') text[0] = static_cast<char>(text[0] - 32);
  return text;
}

// Runs a call of the protocol; on any exception the controller holds, and it passes on.
template <class F>
void Holding(AckController& io, bool& failed, F&& call) {
  try {
    call();
  } catch (...) {
    failed = true;
    io.Hold();
    throw;
  }
}

}  // namespace

AcknowledgedMove::AcknowledgedMove(ControllerOptions& o, const BenchUnits& units,
                                   std::vector<std::uint64_t> moduli, bool shared_status,
                                   std::string_view who)
    : units_(units), moduli_(std::move(moduli)), shared_status_(shared_status) {
  for (std::uint64_t m : moduli_) {
    if (m < 2) throw Error(fmt::format("{}: a sequence modulus of {}: expected 2 or more", who, m));
  }
  settled_ = SettledReadingCheck(ResolveControllerOptions(o, units, moduli_.size(), who));
  ack_timeout_ = o.ack_timeout;
  poll_interval_ = o.poll_interval;
  position_tolerance_ = *o.position_tolerance;
  force_plausible_ = *o.force_plausible;
  last_ack_.assign(moduli_.size(), 0);
}

void AcknowledgedMove::Start(std::span<const std::uint64_t> acks) {
  if (acks.size() != moduli_.size()) {
    throw Error(fmt::format("AcknowledgedMove::Start: {} acks for {} actuators", acks.size(),
                            moduli_.size()));
  }
  last_ack_.assign(acks.begin(), acks.end());
  first_exchange_ = true;
  settled_.Reset();  // the actuator may have been moved while it was not ours
  failed_ = false;
}

std::string AcknowledgedMove::Who(const AckController& io, std::size_t k) const {
  return shared_status_ ? io.Name() : io.Subject(k);
}

void AcknowledgedMove::Fail(AckController& io, const std::string& message) {
  failed_ = true;
  io.Hold();
  throw TransferError(message);
}

void AcknowledgedMove::Move(std::span<const double> commands, std::span<Measurement> out,
                            AckController& io, bool active, const std::string& read_failure) {
  const std::size_t n = moduli_.size();
  const bool several = n > 1;
  const std::string& unit = units_.length_name;
  // 0. Nothing is sent to a controller that is not ours or could not be seen.
  if (commands.size() != n || out.size() != n) {
    throw TransferError(fmt::format("{}: {} commands for {} actuators: nothing was sent",
                                    io.Name(), commands.size(), n));
  }
  const std::string sent =
      fmt::format("command{} {} {}", several ? "s" : "", ValueList(commands), unit);
  if (!active || failed_) {
    throw TransferError(fmt::format(
        "{} is not active (not activated, holding, or the connection was lost): {} not sent; "
        "call Activate() first", io.Name(), sent));
  }
  if (!read_failure.empty()) {
    throw TransferError(fmt::format(
        "{} not sent: the {} could not be read before moving ({}); hybridtest does not move "
        "an actuator it cannot see. Check the link and the controller, then start again "
        "(Activate; `hybridtest resume` again)",
        sent, several ? "actuators' positions" : "actuator's position", read_failure));
  }
  // 1. Every command with its sequence.
  sequence_.resize(n);
  for (std::size_t k = 0; k < n; ++k) sequence_[k] = (last_ack_[k] + 1) % moduli_[k];
  Holding(io, failed_, [&] { io.Write(commands, sequence_); });
  // 2.–4. The acks, then what came with them.
  const std::string waiting =
      fmt::format("while waiting for the ack{} of {} ({})", several ? "s" : "", sent,
                  io.Sequences(sequence_));
  AwaitAcks(io, waiting);
  last_ack_ = sequence_;
  if (first_exchange_) CheckPlausible(commands, io);
  CheckSettled(commands, io);
  first_exchange_ = false;
  for (std::size_t k = 0; k < n; ++k) {
    out[k] = Measurement{reading_[k].position, reading_[k].force, 0.0};
  }
}

void AcknowledgedMove::AwaitAcks(AckController& io, const std::string& waiting) {
  const std::size_t n = moduli_.size();
  const std::string held = io.Held();
  const auto deadline = AckClock::now() + std::chrono::duration<double>(ack_timeout_);
  for (;;) {
    Holding(io, failed_, [&] { io.Read(reading_, waiting); });
    if (reading_.size() != n) {
      Fail(io, fmt::format("{}: a read gave {} actuators, expected {} ({})", io.Name(),
                           reading_.size(), n, waiting));
    }
    // The controller's own stops, on every read.
    for (std::size_t k = 0; k < n; ++k) {
      if (!reading_[k].fault) continue;
      Fail(io, fmt::format("{} reports a fault ({}) {}: {}; {}. Clear the fault at the "
                           "controller before resuming", Who(io, k),
                           io.Where(AckController::Flag::kFault, k), waiting, io.Describe(k),
                           held));
    }
    bool acked = true;
    for (std::size_t k = 0; k < n; ++k) {
      const AckReading& r = reading_[k];
      if (!r.enabled) {
        Fail(io, fmt::format("{} dropped the enable ({}) {}: {}; {}", Who(io, k),
                             io.Where(AckController::Flag::kEnabled, k), waiting, io.Describe(k),
                             held));
      }
      if (r.holding) {
        Fail(io, fmt::format("{} reports holding ({}) {}: {}; it holds on its own (an operator, "
                             "an interlock or its watchdog) and the test stops; {}. Find out "
                             "why it holds, then `hybridtest resume`", Who(io, k),
                             io.Where(AckController::Flag::kHolding, k), waiting,
                             io.Describe(k), held));
      }
      acked = acked && r.ack == sequence_[k];
    }
    if (acked) return;
    // The link works but the controller does not do what it should.
    for (std::size_t k = 0; k < n; ++k) {
      const std::uint64_t ack = reading_[k].ack;
      if (ack == sequence_[k] || ack == last_ack_[k]) continue;
      Fail(io, fmt::format("{} acknowledged {}, expected {} (or the previous {} while moving) "
                           "{}: {}; is another client writing to it? {}", Who(io, k),
                           io.Ack(k, ack), sequence_[k], last_ack_[k], waiting, io.Describe(k),
                           Capitalised(held)));
    }
    if (AckClock::now() >= deadline) {
      std::size_t k = 0;
      while (reading_[k].ack == sequence_[k]) ++k;
      Fail(io, fmt::format("{} did not acknowledge within {} s {}: last read {}; {}", Who(io, k),
                           ack_timeout_, waiting, io.Describe(k), held));
    }
    Holding(io, failed_, [&] { io.Wait(); });
    if (poll_interval_ > 0.0) {
      std::this_thread::sleep_for(std::chrono::duration<double>(poll_interval_));
    }
  }
}

void AcknowledgedMove::CheckPlausible(std::span<const double> commands, AckController& io) {
  for (std::size_t k = 0; k < moduli_.size(); ++k) {
    const AckReading& r = reading_[k];
    const bool position_ok = std::abs(r.position - commands[k]) <= position_tolerance_;
    const bool force_ok = std::abs(r.force) <= force_plausible_;  // false for NaN
    if (position_ok && force_ok) continue;
    Fail(io, fmt::format("implausible first measurement from {}: command {} {}, {}; expected the "
                         "position within {} {} of the command and |force| ≤ {} {}; {}; {}",
                         io.Subject(k), commands[k], units_.length_name, io.Describe(k),
                         position_tolerance_, units_.length_name, force_plausible_,
                         units_.force_name, io.Held(), io.PlausibilityHint()));
  }
}

void AcknowledgedMove::CheckSettled(std::span<const double> commands, AckController& io) {
  const std::size_t n = moduli_.size();
  std::vector<double> positions(n);
  for (std::size_t k = 0; k < n; ++k) positions[k] = reading_[k].position;
  SettledReadingCheck::Source source;
  source.unit = units_.length_name;
  source.metres_per_unit = units_.metres_per_length_unit;
  source.answered = [&](std::size_t k) {
    return fmt::format("{} acknowledged command {} {} ({})", Capitalised(io.Subject(k)),
                       commands[k], units_.length_name,
                       io.Sequences(std::span<const std::uint64_t>(&sequence_[k], 1)));
  };
  source.detail = [&](std::size_t k) { return " (" + io.Describe(k) + ")"; };
  source.after = io.Held();
  source.following_key = "transfer.following_error";
  source.settle_key = "transfer.settle_tolerance";
  Holding(io, failed_, [&] { settled_.Check(commands, positions, source); });
}

}  // namespace hybridtest::transfer
