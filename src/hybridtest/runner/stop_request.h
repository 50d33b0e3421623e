#pragma once
// Interrupted: how a run that was asked to stop (Session::RequestStop, e.g. from the command
// line's SIGINT/SIGTERM handler) reports it. The Session returns kHeld and keeps this as its
// error(): physical substructures hold, every committed step is recorded, and the sidecar
// says "stopped: interrupted ...".
#include "hybridtest/common/error.h"

namespace hybridtest::runner {

class Interrupted : public Error {
 public:
  using Error::Error;
};

}  // namespace hybridtest::runner
