#pragma once
// A cooperative stop for long runs. The command line's SIGINT/SIGTERM handler calls
// RequestStop() (async-signal-safe); HybridTest checks StopRequested() after every committed
// step and then stops like on any failure: physical substructures hold, every committed step is
// in the journal, the sidecar says "stopped: interrupted ...", and Interrupted propagates.
#include "hybridtest/common/error.h"

namespace hybridtest::runner {

// Thrown by HybridTest::Run() when a stop was requested.
class Interrupted : public Error {
 public:
  using Error::Error;
};

void RequestStop() noexcept;
bool StopRequested() noexcept;
void ClearStopRequest() noexcept;

}  // namespace hybridtest::runner
