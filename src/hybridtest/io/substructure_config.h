#pragma once
// The `substructures:` section of a run config: which substructure owns each restoring-force
// slot of the model. Slots not listed get the model's default numerical substructure (a linear
// spring with the model's slot stiffness, k_b q_i for the rotor).
//
//   substructures:
//     r1:
//       type: physical
//       transfer:
//         type: emulated              # emulated | loopback | remote | modbus | openfresco | ads |
//                                     # rt_plant | compensated | fmu (an FMU as the plant,
//                                     # fmi/fmu_plant.h), or a type a program registered
//                                     # (io/transfer_readers.h)
//         config: bench-cantilever.yaml   # emulated: bench file, relative to this config
//         # bench: {...}              # emulated: or the bench inline
//         # law: {type: linear, stiffness: 7200}   # loopback: the specimen law
//         # address: 127.0.0.1:7471   # remote (--bench HOST:PORT overrides it)
//         # token_file: bench.token   # remote: file with the token (or env
//                                     # HYBRIDTEST_BENCH_TOKEN); never `token:` in the config
//         # timeout: 5                # remote: longest wait for one reply [s] (default: safety.timeout)
//       setup: {p0: 0.02, sign: 1, scale: 1, force_sign: 1, force_scale: 1, load_cell_zero: 0}
//       safety: {stroke_min: -0.15, stroke_max: 0.15, max_increment: 0.005,
//                force_soft: 8000, force_hard: 10000, timeout: 5,   # SI: m, N, s
//                initial_stiffness: 5250}   # [N/m] optional: predict forces from the start
//                # remote: a given `safety:` must lie within the limits the bench announces
//                # at connection (transfer/limits_check.h), else ConfigError (a unit slip)
//     r2:
//       type: numerical
//       law: {type: linear, stiffness: 7200}   # or bouc_wen / cantilever (constitutive/)
//     r3:
//       type: fmu                     # an FMU (FMI 2.0/3.0 co-simulation): fmi/fmu_config.h
//       fmu: spring.fmu               # relative to this config
//       displacement: x               # its input and output, by name (lists for `slots:`)
//       force: F
//     blade1:                         # a specimen that serves several slots, on n actuators
//       type: physical
//       slots: [r_flap, r_edge]
//       setup: {p0: [..], transform: [[..]]}   # linear, a = p0 + T d; or the rods of
//                                              # {geometry: large_displacement, ...} (setup_config.h)
//       safety: {..., slots: {max_displacement: [..], max_force: [..]}}   # lists per actuator / slot
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hybridtest/io/config.h"
#include "hybridtest/substructures/substructure.h"
#include "hybridtest/substructures/substructure_spec.h"

namespace hybridtest::io {

struct SubstructureOptions {
  std::optional<std::string> bench_address;  // --bench HOST:PORT for remote transfer systems
  bool allow_physical = true;                // false: a physical slot is a ConfigError
  std::string physical_hint = "give its restoring force explicitly";  // how to fix that error
  // If set: every physical slot's transfer system is the in-process emulated bench of this
  // bench config file instead of the configured one (`hybridtest plan --emulate`).
  std::optional<std::string> emulate_bench;
  // If set, every file the section reads (bench files, token files) is appended here, in the
  // order read (CompileRunSpec keeps them in RunSpec::source.files).
  std::vector<RunInput>* files_read = nullptr;
};

// One spec per slot of cfg.model, in slot order: the section read and checked once (bench
// files, tokens and laws included); building from them reads nothing more.
std::vector<substructures::SubstructureSpec> ParseSubstructureSpecs(
    const SimulationConfig& cfg, const SubstructureOptions& options);

// One substructure per slot of cfg.model, in slot order. Nothing is activated or connected.
std::vector<std::unique_ptr<substructures::Substructure>> MakeSubstructures(
    const SimulationConfig& cfg, const SubstructureOptions& options);

}  // namespace hybridtest::io
