// SiteServer's UI-SimCor codec (site_server.h, simcor_codec.h): a line in, the site's
// transaction rules (Propose, Execute, Query), a line out.
#include <fmt/core.h>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/protocol.h"
#include "hybridtest/transfer/site/site_server.h"

namespace hybridtest::transfer::site {

bool SiteServer::SendLine(Connection& c, const std::string& line) {
  return loop_.Send(c, std::vector<std::uint8_t>(line.begin(), line.end()));
}

bool SiteServer::HandleSimcorLine(Connection& c, std::span<const std::uint8_t> line) {
  Session& session = sessions_[c.id];
  simcor::Request r;
  try {
    r = simcor::ParseLine(line);
  } catch (const TransferError& e) {
    Log(fmt::format("UI-SimCor line refused from {}: {}", c.peer, e.what()));
    SendLine(c, simcor::FormatNotOk(simcor::EchoOf(line), e.what()));
    return c.established;  // a bad first line ends the connection; later ones are answered
  }
  if (!c.established) {
    c.established = true;
    session.run = "ui-simcor:" + c.peer;  // a reconnect from the same address takes over
    Log(fmt::format("UI-SimCor coordinator connected from {}", c.peer));
  }
  if (loop_.commander() == c.id) last_heard_ = Clock::now();
  switch (r.command) {
    case simcor::Command::kOpenSession:
      return SendLine(c, simcor::FormatOk(r.echo, "open-session: hybridtest site " +
                                                      options_.name));
    case simcor::Command::kCloseSession:
      if (loop_.commander() == 0 || loop_.commander() == c.id) {
        HoldBench("the UI-SimCor coordinator said close-session");
      }
      SendLine(c, simcor::FormatOk(r.echo, "close-session"));
      return false;
    case simcor::Command::kPropose: {
      std::vector<simcor::ControlPoint> points = r.points;
      const Verdict v = Propose(c, {r.id, std::move(r.targets)});
      if (v.kind == Verdict::Kind::kAccept) {
        session.points = std::move(points);
        return SendLine(c, simcor::FormatOk(r.echo, "accepted"));
      }
      if (v.kind == Verdict::Kind::kRefuse) {
        return SendLine(c, simcor::FormatNotOk(
                               r.echo, fmt::format("refused: limit {}: {}", v.refusal.limit,
                                                   v.refusal.reason)));
      }
      SendLine(c, simcor::FormatNotOk(r.echo, v.text));
      return v.keep;
    }
    case simcor::Command::kExecute: {
      const Verdict v = Execute(c, r.id);
      if (v.kind == Verdict::Kind::kResult) {
        session.last = v.result.measurements;
        return SendLine(c, simcor::FormatOk(r.echo, v.result.replayed
                                                        ? "executed before: answered from the "
                                                          "record, nothing moved"
                                                        : "executed"));
      }
      SendLine(c, simcor::FormatNotOk(r.echo, v.text));
      return v.keep;
    }
    case simcor::Command::kGetControlPoint:
      return SimcorControlPoints(c, r);
  }
  return false;
}

// get-control-point: the measurements of transaction `r.id` (from the record), or with
// "dummy" of the last RESULT on this connection (before any: read now, nothing moves), for
// each address asked.
bool SiteServer::SimcorControlPoints(Connection& c, const simcor::Request& r) {
  Session& session = sessions_[c.id];
  std::vector<Measurement> measured = session.last;
  if (!r.dummy) {
    const Verdict v = Query(r.id);
    if (v.kind != Verdict::Kind::kResult) return SendLine(c, simcor::FormatNotOk(r.echo, v.text));
    measured = v.result.measurements;
  } else if (measured.empty()) {  // nothing executed on this connection: where it is now
    const Verdict v = Query({"ui-simcor", kQueryNow, -1, 0, 0});
    if (v.kind != Verdict::Kind::kResult) return SendLine(c, simcor::FormatNotOk(r.echo, v.text));
    measured = v.result.measurements;
  }
  std::vector<simcor::PointReading> readings;
  for (const auto& asked : r.points) {
    bool found = false;
    for (std::size_t k = 0; k < session.points.size() && k < measured.size(); ++k) {
      if (session.points[k].address == asked.address) {
        readings.push_back({session.points[k], measured[k]});
        found = true;
      }
    }
    if (!found && measured.size() == 1) {  // one actuator: every address is it
      readings.push_back({{asked.address, "x"}, measured[0]});
      found = true;
    }
    if (!found) {
      return SendLine(c, simcor::FormatNotOk(
                             r.echo, fmt::format("control point {} was not named by the last "
                                                 "accepted propose on this connection",
                                                 asked.address)));
    }
  }
  return SendLine(c, simcor::FormatControlPoints(r.echo, readings));
}

}  // namespace hybridtest::transfer::site
