#pragma once
// SiteServer: one physical site of a multi-site test (docs/multi-site.md). It serves one
// TransferSystem (any the project has, built from the site's config) with the site protocol
// (site_protocol.h) on the project's one ServerLoop (server_loop.h: its limits, one commanding
// connection), behind the site's own SafetyGate (its own limits, per actuator), and decides
// alone:
//  - PROPOSE: the targets are checked by the gate WITHOUT moving (SafetyGate::Vet): ACCEPT
//    (the proposal is kept until executed or replaced by the next one) or REFUSE with the
//    limit, values and reason. A proposal of a key already executed is accepted (its EXECUTE
//    will be answered from the record).
//  - EXECUTE: only the accepted proposal of that key moves the bench (check → move → check
//    through the gate); an id is applied at most once: a repeated EXECUTE (or QUERY) of an
//    executed key is answered with the recorded RESULT (replayed = 1), nothing moves. An
//    EXECUTE of a key never accepted is an ERROR and moves nothing.
//  - QUERY of seq 0 (kQueryNow): every actuator's measurement now (TransferSystem::ReadAll,
//    nothing moves; the coordinator's start check), or ERROR BENCH if the bench cannot read so.
//  - Every executed transaction is appended to the journal (site_journal.h) before it is
//    answered. The journal is bounded (journal_max_bytes: a full journal refuses every new
//    proposal, limit "journal", and holds; refusals_per_minute: a flood of refused proposals
//    holds and is not journaled line by line), so no coordinator — UI-SimCor's carries no
//    token — can fill the site's disk; nothing executed is ever left out.
//  - Watchdog: nothing from the commanding coordinator for `watchdog` [s] → the bench holds
//    (the connection stays; the next EXECUTE resumes with Activate()). HOLD, BYE and the end
//    of the commanding connection hold too. A held bench keeps its accepted proposal.
//  - Token as the bench protocol's (auth.h: bind policy, constant-time compare, throttle).
//    One coordinator commands; a new connection whose HELLO names the same run (client_name
//    = the run tag) takes over from the old one (a reconnect after a lost link).
//  - Two codecs on the one loop, chosen per connection by its first byte: the site protocol
//    (a frame begins with 'H') and, with `simcor`, UI-SimCor's ASCII lines (a lowercase
//    letter; simcor_codec.h). Both go through the same transaction rules (Propose, Execute,
//    Query below). UI-SimCor's protocol has no token, so `simcor` needs a site without one
//    (hence on loopback); a UI-SimCor reconnect from the same address takes over.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "hybridtest/transfer/auth.h"
#include "hybridtest/transfer/frame.h"
#include "hybridtest/transfer/safety_gate.h"
#include "hybridtest/transfer/server_loop.h"
#include "hybridtest/transfer/site/site_journal.h"
#include "hybridtest/transfer/site/site_protocol.h"
#include "hybridtest/transfer/site/simcor_codec.h"
#include "hybridtest/transfer/socket.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer::site {

struct SiteServerOptions {
  std::string name = "site";        // for logs and the WELCOME
  std::string host = "127.0.0.1";   // non-loopback needs `token` (auth.h)
  std::uint16_t port = 0;           // 0 picks a free port
  std::string token;
  std::vector<SafetyLimits> limits;      // per actuator (one set: every actuator), SI
  std::vector<double> start_positions;   // [m] per actuator before the first move; may be empty
  double watchdog = 5.0;           // silence of the coordinator before the bench holds. [s]
  double handshake_timeout = 2.0;  // [s]
  double idle_timeout = 120.0;     // a silent connection is closed after this. [s]
  std::string journal;             // the journal file; empty: in memory only (tests)
  // The journal's size bound: past it, every new proposal is refused (limit "journal") and
  // the site holds; an accepted proposal's execute is always journaled. Unit: [bytes].
  std::uintmax_t journal_max_bytes = std::uintmax_t{1} << 30;
  // Refused proposals journaled per 60 s; beyond, the site holds and further refusals are
  // answered (REFUSE) but not journaled until the rate falls (one journal line says so).
  std::size_t refusals_per_minute = 600;
  bool simcor = false;             // also accept UI-SimCor's ASCII protocol (no token)
  std::function<void(const std::string&)> log;
};

class SiteServer {
 public:
  // Binds and listens. Throws ConfigError (bind policy, limits, journal), TransferError (bind).
  // `bench` must outlive the server.
  SiteServer(TransferSystem& bench, SiteServerOptions options);
  SiteServer(const SiteServer&) = delete;
  SiteServer& operator=(const SiteServer&) = delete;

  std::uint16_t port() const { return listener_.port(); }
  std::string address() const { return listener_.address(); }
  // Activates the bench and serves until Stop(); then holds and deactivates the bench.
  void Serve();
  void Stop() noexcept { stop_.store(true); }
  long executed() const { return executed_.load(); }  // moves made (not replays)
  long holds() const { return holds_.load(); }        // holds entered
  long refusals() const { return refusals_.load(); }

 private:
  using Connection = ServerLoop::Connection;
  using Clock = std::chrono::steady_clock;
  struct Session {
    std::string run;     // the coordinator's run tag (its HELLO's client_name)
    bool chosen = false; // the codec was chosen (by the first byte)
    bool simcor = false; // UI-SimCor's ASCII lines, else the site protocol's frames
    std::vector<simcor::ControlPoint> points;  // UI-SimCor: the last accepted proposal's
    std::vector<Measurement> last;             // UI-SimCor: the last RESULT answered
  };
  // What the transaction rules answer, whatever the codec.
  struct Verdict {
    enum class Kind { kAccept, kRefuse, kResult, kError };
    Kind kind = Kind::kError;
    TransactionId id;
    Refusal refusal;   // kRefuse
    Result result;     // kResult
    int code = 0;      // kError: an ErrorCode
    std::string text;  // kError
    bool keep = true;  // false: close the connection after the answer
  };
  std::size_t Measure(const Connection& c, std::span<const std::uint8_t> bytes);
  bool HandleBytes(Connection& c, std::span<const std::uint8_t> bytes);
  bool Handshake(Connection& c, const Frame& frame);
  bool HandleFrame(Connection& c, const Frame& frame);
  bool Answer(Connection& c, std::uint32_t sequence, const Verdict& v);
  // The transaction rules (one for both codecs).
  Verdict Propose(Connection& c, Proposal p);
  Verdict Execute(Connection& c, const TransactionId& id);
  Verdict Query(const TransactionId& id) const;
  // An error verdict (kBusy) when another coordinator commands, after a reconnect takeover.
  std::optional<Verdict> Claim(Connection& c);
  // UI-SimCor (site_simcor.cc).
  bool HandleSimcorLine(Connection& c, std::span<const std::uint8_t> line);
  bool SimcorControlPoints(Connection& c, const simcor::Request& r);
  bool SendLine(Connection& c, const std::string& line);
  void Closed(Connection& c, const ServerLoop::Closing& closing);
  bool Send(Connection& c, const Frame& frame);
  void SendError(Connection& c, std::uint32_t sequence, int code, const std::string& text);
  // Holds the bench; journals `why` when the hold begins, or always with `note`.
  void HoldBench(const std::string& why, bool note = false);
  // A refusal of `p` by the gate: journaled within refusals_per_minute, else held.
  void RecordRefusal(const Proposal& p, const SafetyStop& e);
  void Log(const std::string& line) const;

  TransferSystem& bench_;
  SiteServerOptions options_;
  BenchUnits units_;
  SafetyGate gate_;
  SiteJournal journal_;
  std::vector<GatedMove> moves_;
  std::vector<double> commands_m_;
  std::optional<Proposal> accepted_;
  Listener listener_;
  std::map<int, Session> sessions_;
  AuthThrottle auth_;
  ServerLoop loop_;
  std::atomic<bool> stop_{false};
  std::atomic<long> executed_{0}, holds_{0}, refusals_{0};
  bool held_ = false;
  Clock::time_point last_heard_ = Clock::now();
  std::deque<Clock::time_point> refused_at_;  // the last refusals (≤ refusals_per_minute + 1)
  bool flooded_ = false;                      // refusals beyond the rate are not journaled
};

}  // namespace hybridtest::transfer::site
