#pragma once
// The state of one OpenFresco session (server.h), shared by the server's files: server.cc
// (openings, the connections) and server_messages.cc (the actions of a session). Internal.
#include <string>
#include <vector>

#include "hybridtest/transfer/openfresco/server.h"

namespace hybridtest::transfer::openfresco {

struct Server::Session {
  Header header;
  std::vector<double> trial_vel;     // last trial velocities (wire units), n or empty
  std::vector<double> trial_accel;   // last trial accelerations (wire units), n or empty
  bool measured = false;             // a trial has been executed in this session
  std::vector<double> offsets;       // (n_act) measured positions − p0. Unit: [m].
  std::vector<double> forces;        // (n_act) measured forces. Unit: [N].
  double lab_time = 0.0;             // lab time of the measurement. Unit: [s].
};

}  // namespace hybridtest::transfer::openfresco
