#pragma once
// The TwinCAT PLC emulator (AdsServer) serving an emulated bench in a background thread, and
// an AdsTransfer pointed at it, for the ADS tests.
#include <memory>
#include <string>

#include "hybridtest/transfer/ads/ads_server.h"
#include "hybridtest/transfer/ads/ads_transfer.h"
#include "hybridtest/transfer/bench_spec.h"
#include "hybridtest/transfer/emulated_bench.h"
#include "transfer/serving_thread.h"

namespace hybridtest::transfer::ads::testing {

inline const std::string kIdealBench = std::string(HYBRIDTEST_SOURCE_DIR) + "/examples/rotor/bench-ideal.yaml";
inline const std::string kTwoActuatorBench =
    std::string(HYBRIDTEST_SOURCE_DIR) + "/examples/06_blade_two_actuators/bench-2act.yaml";

class ServedPlc {
 public:
  // Serves the bench file `bench_file` on 127.0.0.1 (a free port); `edit` adjusts the options.
  template <class Edit>
  ServedPlc(const std::string& bench_file, Edit edit) : spec_(LoadEmulatedBenchSpec(bench_file)) {
    bench_ = MakeEmulatedBench(spec_);
    AdsServerOptions o;
    o.port = 0;
    UseBenchSafety(o, spec_);
    edit(o);
    server_ = std::make_unique<AdsServer>(*bench_, o);
    thread_ = std::make_unique<transfer::testing::ServingThread<AdsServer>>(*server_);
  }
  explicit ServedPlc(const std::string& bench_file) : ServedPlc(bench_file, [](AdsServerOptions&) {}) {}

  // Options of a client of this PLC (n actuators of the default profile).
  AdsOptions Client(int actuators = 1) const {
    AdsOptions o;
    o.endpoint.tcp_port = server_->port();
    o.profile = DefaultProfile(actuators);
    o.ack_timeout = 2.0;
    return o;
  }
  const EmulatedBenchSpec& spec() const { return spec_; }
  AdsServer& server() { return *server_; }

 private:
  EmulatedBenchSpec spec_;
  std::unique_ptr<TransferSystem> bench_;
  std::unique_ptr<AdsServer> server_;
  std::unique_ptr<transfer::testing::ServingThread<AdsServer>> thread_;
};

}  // namespace hybridtest::transfer::ads::testing
