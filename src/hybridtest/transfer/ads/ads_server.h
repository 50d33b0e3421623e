#pragma once
// AdsServer: a TwinCAT PLC emulator serving one TransferSystem (the emulated bench, one or
// several actuators) over ADS: AMS/TCP on port 48898, the PLC runtime at AMS port 851, the
// profile's variables by symbol name (ads_plc_image.h). `hybridtest bench --protocol ads`
// runs it, so that the `ads` transfer (and any ADS client: the npm package ads-client in the
// test suite) can rehearse against it before a real PLC.
//
// Services: ReadDeviceInfo, ReadState (RUN, or the state it is told to show), Read, Write,
// ReadWrite with the index groups of PlcImage and the sum commands 0xF080 (read) and 0xF081
// (write); the AMS/TCP port-connect message of a client without a router (it is given
// "its IPv4 address.1.1" and a port). Anything else: ADS error 0x701. A request addressed to
// another AmsNetId is answered with error 0x7 (target machine not found), to another AMS port
// with 0x6 (target port not found).
//
// Routes: as a TwinCAT router, it serves only the source AmsNetIds in `routes`, each from the
// address its route names; a packet from any other AmsNetId, or a routed AmsNetId claimed from
// another address, is logged and its connection closed without an answer (what an unrouted
// client of a real PLC sees). On loopback an empty list serves every client; on any other
// address the list is required.
//
// Two PLC programs (AdsServerOptions::program). kPHybrid runs docs/ads.md's P_Hybrid, the
// program a PLC engineer writes from the docs, cyclically every cycle_time
// (ads_server_program.cc): live fPosition/fForce every cycle, a command taken when nCommandSeq
// differs from nAckSeq while enabled and not holding, acknowledged the cycle after the move,
// and the heartbeat watchdog (bHold := TRUE when nHeartbeat has not changed for `watchdog`
// seconds while enabled and not held); a connection that ends does not hold it, only the
// watchdog does, as on a PLC. kInstant (the default, for test faults) runs after every write:
//
// The instant program it runs after every write (one "cycle"; in a sum write after all of it):
//   - bEnabled = bEnable and not bFault; bHolding = bHold or bFault; a rising bHold, a fault
//     or a falling bEnabled puts the bench on Hold();
//   - when nCommandSeq differs from the last one seen and from nAckSeq (hybridtest sets
//     nCommandSeq := nAckSeq as it releases a hold), and the PLC is enabled and not holding:
//     every command of fCommand is checked (SafetyGate: stroke, increment, predicted force,
//     coupled with several actuators) and the bench moves all actuators at once; then
//     fPosition, fForce and nAckSeq = nCommandSeq. A refused command or a bench error sets
//     bFault (and holds); a command while not enabled or holding is ignored (no ack);
//   - a fault is cleared by a rising edge of bEnable.
// One client commands: the first to write (a variable, bEnable, a command) owns the drive until
// its connection ends; a write from any other client meanwhile is refused with ADS error 0x704
// (reading or writing not permitted) and changes nothing; every client may read. When the
// commander's connection ends (closed, reset, or silent for idle_timeout) the PLC holds (bHold
// and bHolding TRUE), as a PLC's watchdog would.
// Connections are served by the shared ServerLoop (server_loop.h) with its limits: up to
// max_connections at once, a message complete within message_timeout of its first byte, at
// most 64 KiB + the AMS/TCP prefix per message; a client that drips or idles never delays
// another.
#include <atomic>
#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "hybridtest/transfer/ads/ads_codec.h"
#include "hybridtest/transfer/ads/ads_plc_image.h"
#include "hybridtest/transfer/bench_spec.h"
#include "hybridtest/transfer/safety.h"
#include "hybridtest/transfer/safety_gate.h"
#include "hybridtest/transfer/server_loop.h"
#include "hybridtest/transfer/socket.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer::ads {

// TEST FACILITY ONLY: what the emulator does at the N-th command it receives (N from 1).
struct AdsFault {
  enum class Kind {
    kFault,     // sets bFault instead of acknowledging command N
    kSilence,   // never acknowledges command N or any later one
    kClose,     // closes the connection that wrote command N (the PLC holds)
    kAdsError,  // answers the write of command N with ADS error 0x708 (device busy)
    kHolding,   // acknowledges command N, then reports bHolding as if an operator held
  };
  Kind kind = Kind::kFault;
  long command = 1;
};
// "fault@N", "silence@N", "close@N", "ads_error@N", "holding@N". Throws ConfigError naming
// `where` and the kinds.
AdsFault ParseAdsFault(const std::string& text, const std::string& where);

// A route: the AmsNetId a client presents and the address (numeric IPv4/IPv6) it must come from.
struct AdsRoute {
  AmsNetId net_id;
  std::string address;
};
// "NETID" (the address is the AmsNetId's first four numbers, TwinCAT's convention) or
// "NETID@ADDRESS". Throws ConfigError naming `where` and the form.
AdsRoute ParseAdsRoute(const std::string& text, const std::string& where);

// The PLC program the emulator runs (see above).
enum class PlcProgram { kInstant, kPHybrid };

struct AdsServerOptions {
  std::string host = "127.0.0.1";  // address to bind; off loopback `routes` is required
  std::uint16_t port = kAdsTcpPort;  // 0 picks a free port (see port())
  AmsAddress address{{{127, 0, 0, 1, 1, 1}}, kPlcPort};  // the PLC's AmsNetId and AMS port
  std::vector<AdsRoute> routes;    // clients served; empty on loopback: all
  AdsProfile profile = DefaultProfile();  // symbol names and units (actuators: the bench's)
  std::uint16_t ads_state = kStateRun;    // what ReadState shows (kStateStop to rehearse)
  double idle_timeout = 30.0;      // a client silent this long is dropped. Unit: [s].
  double message_timeout = 2.0;    // a begun message must be complete within. Unit: [s].
  std::size_t max_connections = 16;  // clients at once (server_loop.h)
  SafetyLimits limits;             // checked before every command. SI.
  std::vector<double> start_positions;        // [m] per actuator, for the increment check
  std::optional<double> initial_stiffness;    // [N/m] one actuator's first force prediction
  std::optional<Eigen::MatrixXd> actuator_stiffness;  // [N/m] (n × n) coupled prediction
  PlcProgram program = PlcProgram::kInstant;
  double cycle_time = 0.01;        // kPHybrid: the PLC task's cycle. Unit: [s].
  double watchdog = 2.0;           // kPHybrid: tWatchdog's PT. Unit: [s].
  std::vector<AdsFault> faults;    // TEST FACILITY ONLY (kInstant only)
  std::function<void(const std::string&)> log;  // one line per event; may be empty
};

// Sets the safety of `o` (limits, start positions, the stiffness of the force prediction)
// from an emulated bench's spec, as `hybridtest bench` does for every protocol.
void UseBenchSafety(AdsServerOptions& o, const EmulatedBenchSpec& spec);

class AdsServer {
 public:
  // Binds and listens. Throws ConfigError for a non-loopback host without routes, a profile
  // whose units differ from the bench's or inconsistent limits; TransferError if the address
  // cannot be bound. `bench` must outlive the server.
  AdsServer(TransferSystem& bench, AdsServerOptions options);
  AdsServer(const AdsServer&) = delete;
  AdsServer& operator=(const AdsServer&) = delete;
  ~AdsServer();

  std::uint16_t port() const { return listener_.port(); }
  std::string address() const { return listener_.address(); }
  // "AmsNetId 127.0.0.1.1.1, AMS port 851, routes: any (loopback)".
  std::string DescribeRoutes() const;

  // Activates the bench and serves until Stop(). Throws what the bench's Activate() throws.
  void Serve();
  void Stop() noexcept { stop_.store(true); }

  long commands_received() const { return commands_received_; }
  long refused_connections() const { return loop_.refused_connections(); }
  long loop_turns() const { return loop_.turns(); }  // the loop's wake-ups (server_loop.h)

 private:
  using Client = ServerLoop::Connection;
  // Handles one message (prefix and body) of `client`; false when its connection must end.
  bool HandleMessage(Client& client, std::span<const std::uint8_t> message);
  std::vector<std::uint8_t> Answer(Client& client, const AmsPacket& request, bool& close);
  std::vector<std::uint8_t> AnswerReadWrite(Client& client, const IndexRequest& r, bool& close);
  // The PLC program after a write (see above); `close` set when a test fault
  // closes its connection. Returns 0, or the ADS error of a test fault for the write.
  std::uint32_t Cycle(bool& close);
  // Checks and executes the commands of sequence `sequence` (command number n).
  void Execute(std::uint32_t sequence, long n);
  // Checks fCommand and moves the bench (command number n): true with the actual position and
  // force in actual_; false when refused (bFault set, the bench held).
  bool Move(long n);
  // One cycle of docs/ads.md's P_Hybrid (ads_server_program.cc).
  void ProgramCycle();
  void HoldBench(const std::string& why);
  // Claims the drive for `client` (server_loop.h); false (logged) if another commands.
  bool MayWrite(const Client& client);
  void Closed(const Client& client, const std::string& why, bool commander);
  void Log(const std::string& line) const;

  TransferSystem& bench_;
  AdsServerOptions options_;
  Listener listener_;
  PlcImage image_;
  SafetyGate gate_;
  ServerLoop loop_;  // connections, their limits and the commander
  bool bench_active_ = false;
  bool last_enable_ = false, last_hold_ = false;
  std::uint32_t last_sequence_ = 0;
  bool silenced_ = false;     // a silence fault fired
  long commands_received_ = 0;
  struct Actual {
    std::vector<double> position, force;  // bench units, what the PLC's axes read now
  } actual_;
  struct PHybrid {  // P_Hybrid's own variables (docs/ads.md)
    bool last_enable = false;     // rEnable
    bool moving = false;          // bMoving
    std::uint32_t taken = 0;      // nTaken
    std::uint32_t last_heartbeat = 0;  // nLastHeartbeat
    bool watchdog_in = false;     // tWatchdog.IN and when it became TRUE
    std::chrono::steady_clock::time_point watchdog_since{};
    bool held = false;            // HoldAllAxes() called since the last move
  } program_;
  std::atomic<bool> stop_{false};
};

}  // namespace hybridtest::transfer::ads
