#pragma once
// AdsTransfer: a TransferSystem that drives a Beckhoff TwinCAT PLC over ADS (AMS/TCP, port
// 48898), reading and writing the profile's variables by symbol name (ads_profile.h;
// docs/ads.md). n ≥ 1 actuators, one code path.
//
// Before anything moves (Connect, on the first Activate() or Probe()):
//   1. ReadState: the PLC must be in RUN (a PLC in STOP or CONFIG is refused, the state named);
//   2. for every symbol of the profile, its entry (0xF009 symbol info by name): a symbol the
//      PLC does not know (ADS error 0x710) or whose type or size differs from the profile's
//      is refused, naming the symbol, both types and the fix;
//   3. a handle per symbol (0xF003), used for every later access (0xF005), released at the
//      end (0xF006).
//
// One Execute(commands) is the acknowledged move of a PLC (acknowledged_move.h; docs/safety.md,
// "The acknowledged move of a PLC"), which owns the sequence, the deadlines, the checks and the
// hold on every failure; two round trips when the PLC has settled by the first read. The ADS
// parts (ads_execute.cc):
//   1. one sum write (0xF081): the command array, then nCommandSeq = previous + 1 (mod 2^32);
//   2. sum reads (0xF080) of position, force, nAckSeq, bEnabled, bFault and bHolding (one ack
//      and one status for every actuator: the messages name the PLC);
//   3. the hold: bHold (every actuator holds: the PLC has one hold).
// An ADS error code in an answer is named (0x700 and up) and the PLC holds; a timeout or a
// dropped connection closes the link (the PLC must hold when its client goes).
//
// The heartbeat (nHeartbeat, the PLC's watchdog; docs/ads.md "The watchdog"): +1 (mod 2^32)
// in the sum write of every command and of Activate's release, and written alone at most every
// kHeartbeatPeriod while Execute waits for an ack, Activate waits for the enable and with every
// ReadAll (resume's reads). Probe writes nothing, not even the heartbeat.
//
// ReadAll() reads position and force once, writing only the heartbeat (no move); it never throws, and
// when it cannot read, or the PLC shows a fault, no enable or holding, it returns nullopt and
// the next Execute() refuses to move until the next Activate() (resume must see the actuator).
// Activate() checks for a fault, writes bHold = FALSE, bEnable = TRUE and nCommandSeq = nAckSeq
// (one sum write: a command sent before a hold is never executed after it) and waits until
// bEnabled and not bHolding. Hold() writes bHold = TRUE within hold_timeout and
// never throws. Deactivate() writes bHold = TRUE, bEnable = FALSE, releases the handles and
// closes. Probe() connects (the checks above) and reads once: nothing moves.
#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "hybridtest/transfer/acknowledged_move.h"
#include "hybridtest/transfer/ads/ads_link.h"
#include "hybridtest/transfer/ads/ads_profile.h"
#include "hybridtest/transfer/controller_options.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer::ads {

// The timeouts, the first exchange's plausibility, the PLC's in-position window and the
// following errors are the ControllerOptions (controller_options.h), in the profile's units.
struct AdsOptions : ControllerOptions {
  AdsEndpoint endpoint;
  AdsProfile profile = DefaultProfile();
};

class AdsTransfer final : public TransferSystem {
 public:
  // The longest gap between two heartbeats while hybridtest waits on the PLC. Unit: [s].
  static constexpr double kHeartbeatPeriod = 0.1;

  // Does not connect. Throws ConfigError for bad timeouts, tolerances or profile.
  explicit AdsTransfer(AdsOptions options);
  ~AdsTransfer() override;
  AdsTransfer(const AdsTransfer&) = delete;
  AdsTransfer& operator=(const AdsTransfer&) = delete;

  void Activate() override;
  void Execute(std::span<const double> commands, std::span<Measurement> out) override;
  int num_actuators() const override { return options_.profile.actuators; }
  void Hold() noexcept override;
  void Deactivate() override;
  BenchUnits bench_units() const override { return options_.profile.units; }
  std::string Describe() const override;
  std::optional<std::vector<Measurement>> ReadAll() override;
  std::optional<ProbeReading> Probe() override;

  const AdsOptions& options() const { return options_; }
  bool is_connected() const { return link_.is_open(); }
  long requests() const { return link_.requests(); }  // ADS requests sent (a measure of polling)

 private:
  class Controller;  // the ADS side of the acknowledged move (ads_execute.cc)

  // One sum read of the PLC's outputs.
  struct Readout {
    std::vector<double> position, force;  // n each, bench units
    std::uint32_t ack = 0;
    bool enabled = false, fault = false, holding = false;
  };

  // Connects and checks state and symbols, then takes the handles (steps 1–3 above).
  void Connect();
  void CheckSymbol(Role role);
  void ReleaseHandles() noexcept;
  // The write of `roles` with `values` in one sum write; AdsError names the symbol refused.
  void WriteSymbols(std::span<const Role> roles, std::span<const std::vector<std::uint8_t>> values,
                    double timeout, const std::string& what);
  Readout ReadOutputs(const std::string& what);
  // The heartbeat (ads_heartbeat.cc): the next nHeartbeat as bytes, for a sum write that
  // carries it; BeatIfDue() writes it alone if kHeartbeatPeriod has passed since the last;
  // BeatWhileWaiting() too, an ADS error setting bHold and throwing TransferError.
  std::vector<std::uint8_t> NextHeartbeat();
  void BeatIfDue();
  void BeatWhileWaiting();
  std::string Describe(const Readout& r) const;
  std::string Subject() const;  // "the PLC at … (AmsNetId …)"
  // Sets bHold (best effort) and throws TransferError `message`.
  [[noreturn]] void HoldAndFail(const std::string& message);
  // Throws for bFault (before or during a move: `during`).
  void CheckFault(const Readout& r, const std::string& during);
  double WallSinceActivate() const;

  AdsOptions options_;
  AdsLink link_;
  std::vector<std::uint32_t> handles_;  // by Role, once connected
  bool active_ = false;
  AcknowledgedMove move_;  // the sequence, the checks and the last ack
  std::chrono::steady_clock::time_point activated_at_{};
  bool clock_started_ = false;
  std::string read_failure_;
  std::uint32_t heartbeat_ = 0;
  std::chrono::steady_clock::time_point last_beat_{};
};

}  // namespace hybridtest::transfer::ads
