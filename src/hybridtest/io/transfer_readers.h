#pragma once
// The transfer types a run config can name (`transfer: {type: ...}`), each with its reader:
// the reader checks the section's keys and values once (errors name file:line, the key and
// the fix) and returns a substructures::TransferSpec whose factory builds the transfer
// system from what was read. The built-in types are emulated, loopback, remote, site, modbus, ads,
// openfresco, rt_plant, compensated and fmu (an FMU as the plant, fmi/fmu_plant.h); a program adds its own with RegisterTransferReader before it loads a config.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "hybridtest/common/yaml_input.h"
#include "hybridtest/io/run_input.h"
#include "hybridtest/substructures/substructure_spec.h"
#include "hybridtest/transfer/safety.h"

namespace hybridtest::io {

// What a reader gets: the `transfer:` mapping at key path `kp` of config `in`.
struct TransferReadContext {
  const YamlInput& in;
  const YAML::Node& node;
  const std::string& kp;
  std::optional<std::string> bench_address;  // --bench HOST:PORT, if given
  double reply_timeout = 5.0;                // the slot's safety.timeout [s]
  const transfer::SafetyLimits* limits = nullptr;  // the slot's own limits, if it gave them
  // A reader that opens a file (a bench file, a token file) appends it here, so that the run's
  // record and its output guards name every file the run read (null: nobody asks).
  std::vector<RunInput>* files_read = nullptr;
  void NoteRead(std::string role, std::string path) const {
    if (files_read != nullptr) files_read->push_back({std::move(role), std::move(path)});
  }
};

using TransferReader = std::function<substructures::TransferSpec(const TransferReadContext&)>;

// Adds (or replaces) the reader of `type`. Not thread-safe: register before loading configs.
void RegisterTransferReader(const std::string& type, TransferReader reader);

// The registered types, sorted.
std::vector<std::string> TransferTypes();

// The token of a networked transfer section: `token_file: PATH` (relative to the config), else
// HYBRIDTEST_BENCH_TOKEN, else empty. A `token:` written in the config is refused (ConfigError:
// the config is copied into the results).
std::string ReadTransferToken(const TransferReadContext& context);

// Reads the section with the reader its `type` names. Throws ConfigError for a missing or
// unknown type (listing the registered ones) and whatever the reader throws.
substructures::TransferSpec ReadTransfer(const TransferReadContext& context);

// The emulated bench of the bench file `path` (either form, transfer/bench_spec.h: one
// actuator, or `actuators: n` on one coupled specimen), read once, as a transfer of type
// "emulated": what `type: emulated` with `config: FILE` builds, and what `plan --emulate
// BENCH.yaml` stands in for every physical slot with. Throws ConfigError naming the file, the
// key and the fix.
substructures::TransferSpec EmulatedTransfer(const std::string& path);

}  // namespace hybridtest::io
