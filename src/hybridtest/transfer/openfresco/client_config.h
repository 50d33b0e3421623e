#pragma once
// The run-config form of the OpenFresco client (client.h), a substructure's `transfer:`:
//
//   transfer:
//     type: openfresco
//     host: 127.0.0.1                # the site server (--bench HOST:PORT overrides host and port)
//     port: 8090
//     units: {length: mm, force: N}  # units of the numbers on the wire (default mm, N)
//     timeout: 5                     # longest wait for one reply [s] (default: safety.timeout)
//     dofs: 2                        # the element's degrees of freedom n (default 1): one per
//                                    # actuator of the substructure's setup (the rows of its
//                                    # setup.transform; 1 for a one-slot substructure). With
//                                    # n > 1 the substructure serves n slots with T = identity
//                                    # and p0 = 0: the site applies its own setup.
//     token_file: bench.token        # only for a hybridtest server that has a token: a file
//                                    # (relative to the run config) whose first line is the
//                                    # token; without it, HYBRIDTEST_BENCH_TOKEN if set.
//                                    # An inline `token:` is refused (ConfigError): the config
//                                    # text is copied into the results.
#include <memory>
#include <optional>
#include <string>

#include <yaml-cpp/yaml.h>

#include "hybridtest/common/yaml_input.h"
#include "hybridtest/transfer/openfresco/client.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer::openfresco {

// `node` is the `transfer:` mapping at key path `kp`; `bench_address` is --bench when given;
// `reply_timeout` [s] is used unless `timeout:` is given. Throws ConfigError naming the key,
// and naming `dofs` and the fix when the section is a run-config substructure's transfer
// (kp "substructures.NAME.transfer") whose actuators are not `dofs` in number.
ClientOptions ParseClientOptions(const YamlInput& in, const YAML::Node& node,
                                 const std::string& kp,
                                 const std::optional<std::string>& bench_address,
                                 double reply_timeout);
// The client for the section (not connected).
std::unique_ptr<TransferSystem> MakeClientTransfer(const YamlInput& in, const YAML::Node& node,
                                                   const std::string& kp,
                                                   const std::optional<std::string>& bench_address,
                                                   double reply_timeout);

}  // namespace hybridtest::transfer::openfresco
