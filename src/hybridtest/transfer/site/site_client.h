#pragma once
// SiteClient: the coordinator's TransferSystem for one physical site (docs/multi-site.md),
// `transfer: {type: site, address: HOST:PORT, ...}`. A move is a transaction of the site
// protocol (site_protocol.h):
//   Propose(commands, step, stage)  sends PROPOSE (id = run, seq, step, stage, attempt)
//   AwaitVerdict()                  ACCEPT, or REFUSE → SafetyStop naming the site and limit
//   Release()                       sends EXECUTE, does not wait
//   Execute(commands, out)          collects the RESULT of the released transaction; a move
//                                   that was not proposed (a K0 ramp, a start walk, a resume)
//                                   is proposed, judged and executed here, one site alone.
//   ReadAll()                       QUERY of seq 0: where the site's actuators are now, read
//                                   by the site without moving (the start check); nullopt if
//                                   the site cannot read so or does not answer in time.
// Every wait is bounded by its phase's time-out (propose_timeout, execute_timeout). A lost
// link (a time-out, a closed connection) calls the OnLinkLost handler once (the Session
// holds the other sites), then reconnects with backoff (0.1 s doubling to 2 s) until
// reconnect_wait [s] has passed, and repeats the transaction with the SAME id: PROPOSE, then
// EXECUTE if it was released (the site applies an id at most once and answers a repeated
// EXECUTE from its record). Not back in time: TransferError (the run stops, exit 4, every
// committed step on disk; `hybridtest resume` continues).
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "hybridtest/transfer/protocol.h"
#include "hybridtest/transfer/site/site_protocol.h"
#include "hybridtest/transfer/socket.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer::site {

struct SiteClientOptions {
  std::string name = "site";        // the site in messages (the config's key path)
  std::string host = "127.0.0.1";
  std::uint16_t port = 0;
  std::string token;
  int actuators = 1;                // what the config expects (the WELCOME must agree)
  double connect_timeout = 2.0;     // one connection attempt. [s]
  double propose_timeout = 5.0;     // longest wait for ACCEPT/REFUSE. [s]
  double execute_timeout = 30.0;    // longest wait for a RESULT (the site's move). [s]
  double hold_timeout = 0.5;        // longest wait for HOLD_ACK. [s]
  double reconnect_wait = 10.0;     // how long a lost link is waited for. [s]
  std::string run;                  // run tag; empty: one is chosen (per process)
};

class SiteClient final : public TransferSystem {
 public:
  explicit SiteClient(SiteClientOptions options);  // ConfigError for bad times
  ~SiteClient() override;

  void Activate() override;
  int num_actuators() const override { return options_.actuators; }
  void Execute(std::span<const double> commands, std::span<Measurement> out) override;
  void Propose(std::span<const double> commands, long step, int stage) override;
  void AwaitVerdict() override;
  void Release() override;
  bool two_phase() const override { return true; }
  void OnLinkLost(std::function<void()> hold_others) override {
    link_lost_ = std::move(hold_others);
  }
  void Hold() noexcept override;
  void Deactivate() override;
  std::optional<std::vector<Measurement>> ReadAll() override;
  BenchUnits bench_units() const override;
  std::string Describe() const override;
  BenchAnnouncement Announce() const override;

  long reconnects() const { return reconnects_; }
  const std::string& run() const { return options_.run; }
  std::uint64_t bytes_sent() const { return bytes_sent_; }      // [bytes]
  std::uint64_t bytes_received() const { return bytes_received_; }  // [bytes]

 private:
  enum class Phase { kIdle, kProposed, kAccepted, kReleased };
  std::string Endpoint() const;
  void Connect();  // TCP, HELLO, WELCOME; throws TransferError
  // Sends `frame`; false if the link is lost.
  bool SendFrame(const Frame& frame);
  // The reply to request `sequence` (earlier replies of other requests are kept aside);
  // nullopt on a lost link (time-out or closed).
  std::optional<Frame> Await(std::uint32_t sequence, double timeout);
  // The link is lost (`why`): hold the others, reconnect within reconnect_wait, or throw.
  void Recover(const std::string& why);
  // Sends the current transaction's PROPOSE (and EXECUTE if released) again, after Recover.
  void Resend();
  [[noreturn]] void Fail(const std::string& what) const;

  SiteClientOptions options_;
  Socket socket_;
  std::optional<WelcomeMessage> welcome_;
  std::uint32_t next_sequence_ = 1;
  std::uint32_t seq_ = 0;  // transactions of this run at this site
  long last_step_ = -1;
  int last_stage_ = -1, attempt_ = 0;
  Proposal proposal_;
  Phase phase_ = Phase::kIdle;
  std::uint32_t propose_request_ = 0, execute_request_ = 0;  // their frames' sequence numbers
  std::map<std::uint32_t, Frame> early_;  // replies to earlier requests, by sequence (≤ 8)
  std::string loss_;  // why the last Await came back empty (for messages)
  std::function<void()> link_lost_;
  long reconnects_ = 0;
  std::uint64_t bytes_sent_ = 0, bytes_received_ = 0;
};

}  // namespace hybridtest::transfer::site
