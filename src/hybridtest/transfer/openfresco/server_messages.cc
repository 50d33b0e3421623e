// See server.h: the actions of an open session (trial, getters, DAQ, end of session).
#include <fmt/core.h>
#include <poll.h>

#include <cmath>
#include <span>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/openfresco/server.h"
#include "hybridtest/transfer/openfresco/server_session.h"

namespace hybridtest::transfer::openfresco {
namespace {

// True if the peer of `fd` has closed or reset its end, even with bytes still unread.
bool PeerHasLeft(int fd) {
  pollfd p{fd, POLLRDHUP, 0};
  if (poll(&p, 1, 0) < 0) return false;
  return (p.revents & (POLLRDHUP | POLLHUP | POLLERR)) != 0;
}

}  // namespace

bool Server::HandleMessage(Connection& c, Session& session,
                           const std::vector<double>& message) {
  const int n = setup_.dofs();
  const int action = ActionOf(message);
  switch (action) {
    case static_cast<int>(Action::kSetTrialResponse):
      return HandleTrial(c, session, message);
    case static_cast<int>(Action::kCommitState):
      return true;
    case static_cast<int>(Action::kGetDaqResponse):
      return Reply(c, session, DaqResponse(session));
    case static_cast<int>(Action::kGetDisp):
      if (!session.measured) return Reply(c, session, std::vector<double>(n, 0.0));
      return Reply(c, session, ElementDisplacement(setup_, session.offsets));
    case static_cast<int>(Action::kGetVel):
      return Reply(c, session, session.trial_vel.empty()
                                ? std::vector<double>(n, 0.0)
                                : ProjectOnActuators(setup_, session.trial_vel));
    case static_cast<int>(Action::kGetAccel):
      return Reply(c, session, session.trial_accel.empty()
                                ? std::vector<double>(n, 0.0)
                                : ProjectOnActuators(setup_, session.trial_accel));
    case static_cast<int>(Action::kGetForce):
      return Reply(c, session, session.measured ? ElementForces(setup_, session.forces)
                                             : std::vector<double>(n, 0.0));
    case static_cast<int>(Action::kGetTime):
      return Reply(c, session, {session.lab_time});
    case static_cast<int>(Action::kGetInitialStiff):
    case static_cast<int>(Action::kGetTangentStiff):
      return Reply(c, session, ElementStiffness(setup_));
    case static_cast<int>(Action::kGetDamp):
    case static_cast<int>(Action::kGetMass):
      return Reply(c, session, std::vector<double>(static_cast<std::size_t>(n) * n, 0.0));
    case static_cast<int>(Action::kShutdown):
      HoldBench("client sent shutdown (98)");
      return false;
    case static_cast<int>(Action::kDie):
      HoldBench("client ended the session (99)");
      return false;
    default:
      Log(fmt::format("ERROR: action {} ({}) is not served; expected 3, 5, 6, 7-15, 98 or 99",
                      message.empty() ? 0.0 : message[0], ActionName(action)));
      HoldBench("unknown action");
      return false;
  }
}

bool Server::HandleTrial(Connection& c, Session& session,
                         const std::vector<double>& message) {
  const auto& size = session.header.size_ctrl;
  // A trial whose client is gone (it gave up waiting, or vanished) is stale: never executed.
  if (PeerHasLeft(c.socket.fd())) {
    Log(fmt::format("ERROR: trial {} not executed: the client at {} has closed its connection "
                    "(a trial whose client is gone never moves the bench)", trials_.load() + 1,
                    c.peer));
    HoldBench("client left before its trial was executed");
    return false;
  }
  const long count = ++trials_;
  // [3 | d | v | a | force | time]: every value must be finite.
  const std::size_t used = 1 + static_cast<std::size_t>(size[0] + size[1] + size[2] + size[3] +
                                                        size[4]);
  for (std::size_t i = 1; i < used; ++i) {
    if (!std::isfinite(message[i])) {
      Log(fmt::format("ERROR: trial {}: word {} is {}; expected finite values", count, i,
                      message[i]));
      HoldBench("non-finite trial response");
      return false;
    }
  }
  const std::span<const double> words(message);
  const auto block = [&](int index) {
    std::size_t start = 1;
    for (int k = 0; k < index; ++k) start += static_cast<std::size_t>(size[k]);
    return std::vector<double>(words.begin() + static_cast<long>(start),
                               words.begin() + static_cast<long>(start + size[index]));
  };
  const std::vector<double> d = block(kDisp);
  session.trial_vel = size[kVel] == size[kDisp] ? block(kVel) : std::vector<double>();
  session.trial_accel = size[kAccel] == size[kDisp] ? block(kAccel) : std::vector<double>();
  // Check, move, check, as BenchServer does: every actuator's command checked before any
  // moves; a refusal or a bench failure ends the session.
  const auto resume = [&] {
    if (bench_held_) {
      bench_.Activate();
      bench_held_ = false;
    }
  };
  try {
    gate_.Move(bench_, ActuatorCommands(setup_, d), {count, 0},
               std::vector<double>(setup_.p0s.size(), 0.0), moves_, resume);
    session.offsets.clear();
    session.forces.clear();
    for (std::size_t k = 0; k < moves_.size(); ++k) {
      session.offsets.push_back(moves_[k].position - setup_.p0s[k]);
      session.forces.push_back(moves_[k].force);
    }
    session.measured = true;
    session.lab_time = moves_[0].lab_time;
    return true;
  } catch (const SafetyStop& e) {
    Log(fmt::format("ERROR: safety refusal at trial {} ({}): {}", count, e.limit(), e.what()));
    HoldBench(fmt::format("safety refusal at trial {}", count));
  } catch (const Error& e) {
    Log(fmt::format("ERROR: the bench failed to execute trial {}: {}", count, e.what()));
    HoldBench(fmt::format("bench failure at trial {}", count));
  }
  return false;
}

std::vector<double> Server::DaqResponse(const Session& session) const {
  // Blocks disp | vel | accel | force | time: word i of the disp and force blocks holds
  // actuator i's offset and force, word 0 of the time block the lab time; the rest is zero.
  const auto& size = session.header.size_daq;
  std::vector<double> out;
  for (int k = 0; k < 5; ++k) {
    for (int i = 0; i < size[k]; ++i) {
      const auto a = static_cast<std::size_t>(i);
      double v = 0.0;
      if (session.measured) {
        v = k == 0 && a < session.offsets.size()
                ? session.offsets[a] / setup_.wire_units.metres_per_length_unit
            : k == 3 && a < session.forces.size()
                ? session.forces[a] / setup_.wire_units.newtons_per_force_unit
            : k == 4 && i == 0 ? session.lab_time
                               : 0.0;
      }
      out.push_back(v);
    }
  }
  return out;
}

}  // namespace hybridtest::transfer::openfresco
