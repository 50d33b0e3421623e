#pragma once
// The `transfer: {type: ads}` section of a physical substructure (docs/ads.md):
//
//   transfer:
//     type: ads
//     host: 192.168.0.20        # the PLC's IP address (--bench HOST:PORT overrides host and
//     port: 48898               #   port; 48898 is AMS/TCP)
//     ams_net_id: 5.80.201.232.1.1   # the PLC's AmsNetId (default: host's IPv4 address + .1.1)
//     ams_port: 851             # the PLC runtime (TwinCAT 3 PLC 1: 851; TwinCAT 2: 801)
//     local_ams_net_id: 192.168.0.5.1.1   # this computer's AmsNetId, as the PLC's route names
//                               #   it (default: the connection's local IPv4 address + .1.1)
//     local_ams_port: 32905     # the AMS port hybridtest's requests come from
//     actuators: 1              # n: the arrays are ARRAY [1..n] OF LREAL
//     units: {length: mm, force: N}   # of fCommand, fPosition and fForce
//     symbols: {command: GVL_Hybrid.fCommand, ...}   # any of the ten; ads_profile.h
//     timeout: 5                # [s] longest wait for the ack of one command (default: the
//                               #   substructure's safety.timeout)
//     response_timeout: 1       # [s] longest wait for the answer to one request
//     connect_timeout: 5        # [s] longest wait for the TCP connection
//     hold_timeout: 0.5         # [s] longest wait for the answer to the hold write
//     poll_interval: 0          # [s] pause between two reads while waiting for the ack
//     plausibility: {position_tolerance: 1, force: 1e6}   # first exchange, bench units
//     settle_tolerance: 0.05    # the PLC's in-position window, in the length unit
//     following_error: 0.2      # largest |command − position| once acknowledged; one value,
//                               #   or a list of one per actuator (safety_settled_reading.h)
#include <optional>
#include <string>

#include <yaml-cpp/yaml.h>

#include "hybridtest/common/yaml_input.h"
#include "hybridtest/transfer/ads/ads_transfer.h"
#include "hybridtest/transfer/safety.h"

namespace hybridtest::transfer::ads {

// Reads the section at key path `kp`. `bench_address` (--bench HOST:PORT) overrides host and
// port; `default_timeout` [s] is the ack timeout unless `timeout` is given; `limits` are the
// slot's safety limits (SI; null: defaults): following_error defaults to four
// settle_tolerance, at most their max_increment. Throws ConfigError naming the key.
AdsOptions ParseAdsOptions(const YamlInput& in, const YAML::Node& node, const std::string& kp,
                           const std::optional<std::string>& bench_address,
                           double default_timeout, const SafetyLimits* limits = nullptr);

}  // namespace hybridtest::transfer::ads
