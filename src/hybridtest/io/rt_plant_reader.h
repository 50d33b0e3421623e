#pragma once
// Readers of the real-time transfer types (registered in transfer_readers.cc):
//
//   transfer:
//     type: rt_plant
//     plant: servo_hydraulic    # ideal | electromechanical | servo_hydraulic
//     actuators: 1              # n (1 to 64); the keys below then take a number (every
//                               # actuator) or a list of n (one per actuator)
//     delay: 0.0                # [s] pure delay added to the plant
//     lag: 0.01                 # [s] electromechanical time constant
//     rate_hz: 4096             # [Hz] the plant's integration rate (one for all)
//     p0: 0.0                   # [m]
//     specimen: {mass: 29.13, stiffness: 1.19e6, zeta: 0.0097}   # or damping: c [N·(s/m)^α]
//                                                                 # and damping_exponent: α
//     servo: {a1_beta0: 2.1283e13, a2: 4.2297e6, beta1: 425, beta2: 9.9976e4, a3: 3.3,
//             gain: 1.0261}     # optional: the vRTHS nominal values are the defaults; a list
//                               # of n mappings: one per actuator
//
// For n actuators the specimen is in actuator coordinates: `mass` per actuator [kg],
// `stiffness` [N/m] and `damping` a number (on the diagonal), a list of n (the diagonal) or n
// rows of n (the coupled matrix); `zeta` a number or a list (c_ii = 2 ζ_i √(K_ii m_i)).
//
// `type: loopback` (transfer_readers.cc) takes `law:` a law or a list of one law per actuator,
// and `p0:` a number or one per actuator.
//
// and `type: compensated` (transfer/delay_compensator.h), which wraps any other transfer.
#include "hybridtest/io/transfer_readers.h"
#include "hybridtest/transfer/rt_plant.h"

namespace hybridtest::io {

substructures::TransferSpec ReadRtPlant(const TransferReadContext& context);
// The plant config alone (for the stability check and the tests).
transfer::RtPlantConfig ReadRtPlantConfig(const TransferReadContext& context);
substructures::TransferSpec ReadCompensated(const TransferReadContext& context);

}  // namespace hybridtest::io
