#pragma once
// The ADS profile: the PLC variables hybridtest reads and writes by symbol name, their IEC
// 61131-3 types and units (docs/ads.md for the PLC engineer). For n actuators:
//
//   role      default symbol             type                    unit  written by
//   command   GVL_Hybrid.fCommand        ARRAY [1..n] OF LREAL   mm    hybridtest
//   sequence  GVL_Hybrid.nCommandSeq     UDINT                   –     hybridtest (+1 a command)
//   position  GVL_Hybrid.fPosition       ARRAY [1..n] OF LREAL   mm    PLC (measured)
//   force     GVL_Hybrid.fForce          ARRAY [1..n] OF LREAL   N     PLC (measured)
//   ack       GVL_Hybrid.nAckSeq         UDINT                   –     PLC (= nCommandSeq once
//                                                                        settled and sampled)
//   enable    GVL_Hybrid.bEnable         BOOL                    –     hybridtest
//   hold      GVL_Hybrid.bHold           BOOL                    –     hybridtest
//   enabled   GVL_Hybrid.bEnabled        BOOL                    –     PLC
//   fault     GVL_Hybrid.bFault          BOOL                    –     PLC
//   holding   GVL_Hybrid.bHolding        BOOL                    –     PLC
//   heartbeat GVL_Hybrid.nHeartbeat      UDINT                   –     hybridtest (+1 with every
//                                                                        command and while it waits;
//                                                                        the PLC's watchdog)
//
// Every name and both units are configurable (`transfer.symbols`, `transfer.units`). The PLC
// takes a command when nCommandSeq changes, and one sequence serves every actuator.
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer::ads {

enum Role : std::size_t {
  kCommand, kSequence, kPosition, kForce, kAck, kEnable, kHold, kEnabled, kFault, kHolding,
  kHeartbeat, kNumRoles
};

// The config key of a role under `transfer.symbols` ("command", "sequence", …).
const char* RoleKey(Role role);
// The default symbol of a role ("GVL_Hybrid.fCommand", …).
std::string DefaultSymbol(Role role);

// What a role's symbol must be on the PLC for n actuators.
struct ExpectedSymbol {
  std::string type;          // IEC 61131-3 type as TwinCAT names it: "ARRAY [1..2] OF LREAL"
  std::uint32_t size = 0;    // [bytes]
  bool hybridtest_writes = false;
};
ExpectedSymbol Expected(Role role, int actuators);

struct AdsProfile {
  std::array<std::string, kNumRoles> symbols;  // by Role; DefaultProfile fills them
  BenchUnits units{1e-3, 1.0, "mm", "N"};      // of command, position and force
  int actuators = 1;                           // n
};
AdsProfile DefaultProfile(int actuators = 1);

// Values of the profile's types as bytes (little-endian, as on the PLC).
std::vector<std::uint8_t> EncodeReals(std::span<const double> values);  // ARRAY OF LREAL
std::vector<double> DecodeReals(std::span<const std::uint8_t> bytes);   // size / 8 values
std::vector<std::uint8_t> EncodeUdint(std::uint32_t value);
std::vector<std::uint8_t> EncodeBool(bool value);  // one byte, 0 or 1
// A UDINT or BOOL read back (a BOOL is true when its byte is not 0).
std::uint32_t DecodeUdint(std::span<const std::uint8_t> bytes);
bool DecodeBool(std::span<const std::uint8_t> bytes);

}  // namespace hybridtest::transfer::ads
