// See site_server.h.
#include "hybridtest/transfer/site/site_server.h"

#include <fmt/core.h>

#include "hybridtest/common/error.h"
#include "hybridtest/common/text.h"
#include "hybridtest/transfer/protocol.h"

namespace hybridtest::transfer::site {
namespace {

std::vector<SafetyLimits> SiteLimits(const SiteServerOptions& o, int actuators) {
  if (o.limits.empty()) {
    throw ConfigError(fmt::format("site {}: give the site's safety limits", o.name));
  }
  if (o.limits.size() != 1 && static_cast<int>(o.limits.size()) != actuators) {
    throw ConfigError(fmt::format("site {}: {} sets of safety limits for {} actuators; give one "
                                  "set (every actuator) or one per actuator", o.name,
                                  o.limits.size(), actuators));
  }
  if (o.limits.size() == 1) {
    return std::vector<SafetyLimits>(static_cast<std::size_t>(actuators), o.limits[0]);
  }
  return o.limits;
}

const std::string& CheckedHost(const SiteServerOptions& o) {
  CheckBindPolicy(o.host, o.port, o.token, "the site");
  if (o.simcor && !o.token.empty()) {
    throw ConfigError(fmt::format("site {}: --simcor with a token: UI-SimCor's protocol carries "
                                  "no token; serve UI-SimCor on loopback without a token (and "
                                  "reach it through an SSH tunnel)", o.name));
  }
  if (!(o.watchdog > 0.0) || !(o.handshake_timeout > 0.0) || !(o.idle_timeout > 0.0)) {
    throw ConfigError(fmt::format("site {}: watchdog = {} s, handshake_timeout = {} s, "
                                  "idle_timeout = {} s: expected positive times", o.name,
                                  o.watchdog, o.handshake_timeout, o.idle_timeout));
  }
  return o.host;
}

constexpr int kProtocolError = static_cast<int>(ErrorCode::kProtocol);

}  // namespace

SiteServer::SiteServer(TransferSystem& bench, SiteServerOptions options)
    : bench_(bench),
      options_(std::move(options)),
      units_(bench.bench_units()),
      gate_(SiteLimits(options_, bench.num_actuators())),
      journal_(options_.journal),
      listener_(CheckedHost(options_), options_.port),
      loop_(listener_,
            {.max_connections = 8,
             .max_frame_bytes = kFrameHeaderSize + kMaxPayloadLength + kFrameTrailerSize,
             .max_opening_bytes = kFrameHeaderSize + 4096 + kFrameTrailerSize,
             .handshake_timeout = options_.handshake_timeout,
             .frame_timeout = options_.handshake_timeout,
             .idle_timeout = options_.idle_timeout,
             .send_timeout = 2.0,
             .poll_ms = 20},
            [this](const Connection& c, std::span<const std::uint8_t> bytes) {
              return Measure(c, bytes);
            },
            {.opened = [this](Connection& c) { return sessions_.try_emplace(c.id).second; },
             .frame = [this](Connection& c, std::span<const std::uint8_t> bytes) {
               return HandleBytes(c, bytes);
             },
             .closed = [this](Connection& c, const ServerLoop::Closing& closing) {
               Closed(c, closing);
             }},
            [this](const std::string& line) { Log(line); }) {
  for (int k = 0; k < gate_.size(); ++k) {
    const auto i = static_cast<std::size_t>(k);
    if (i < options_.start_positions.size()) {
      gate_.monitor(k).SetStartPosition(options_.start_positions[i]);
    }
  }
}

void SiteServer::Log(const std::string& line) const {
  if (options_.log) options_.log(Printable(line));
}

void SiteServer::HoldBench(const std::string& why) {
  bench_.Hold();
  if (!held_) ++holds_;
  held_ = true;
  journal_.Held(why);
  Log(fmt::format("holding: {}", why));
}

void SiteServer::Serve() {
  bench_.Activate();
  // Where the actuators are, if the config does not say and the bench can tell without moving:
  // the first move's increment is checked from there.
  if (options_.start_positions.empty()) {
    if (const auto now = bench_.ReadAll(); now && static_cast<int>(now->size()) == gate_.size()) {
      for (int k = 0; k < gate_.size(); ++k) {
        gate_.monitor(k).SetStartPosition((*now)[static_cast<std::size_t>(k)].position *
                                          units_.metres_per_length_unit);
      }
    }
  }
  Log(fmt::format("site {} serving {} on {}", options_.name, bench_.Describe(), address()));
  while (!stop_.load()) {
    loop_.Turn();
    // The watchdog: a silent coordinator leaves the bench holding.
    const double silent = std::chrono::duration<double>(Clock::now() - last_heard_).count();
    if (!held_ && loop_.commander() != 0 && silent > options_.watchdog) {
      HoldBench(fmt::format("watchdog: nothing from the coordinator for {} s", options_.watchdog));
    }
  }
  loop_.CloseAll("the site stops");
  HoldBench("site stopping");
  bench_.Deactivate();
  Log("stopped");
}

bool SiteServer::Send(Connection& c, const Frame& frame) {
  return loop_.Send(c, EncodeFrame(frame));
}

void SiteServer::SendError(Connection& c, std::uint32_t sequence, int code,
                           const std::string& text) {
  ErrorMessage m;
  m.code = static_cast<ErrorCode>(code);
  m.text = text.size() > 4000 ? text.substr(0, 4000) : text;
  Log(fmt::format("ERROR {} (sequence {}): {}", ErrorCodeName(static_cast<std::uint16_t>(code)),
                  sequence, m.text));
  Send(c, EncodeError(sequence, m));
}

std::size_t SiteServer::Measure(const Connection& c, std::span<const std::uint8_t> bytes) {
  Session& s = sessions_[c.id];
  if (!s.chosen) {  // the connection's first byte chooses its codec
    s.chosen = true;
    s.simcor = options_.simcor && simcor::BeginsLine(bytes[0]);
  }
  return s.simcor ? simcor::MeasureLine(bytes) : FrameSize(bytes);
}

bool SiteServer::HandleBytes(Connection& c, std::span<const std::uint8_t> bytes) {
  if (sessions_[c.id].simcor) return HandleSimcorLine(c, bytes);
  Frame frame;
  try {
    frame = DecodeFrame(bytes);
  } catch (const TransferError& e) {
    SendError(c, 0, kProtocolError, e.what());
    return false;
  }
  if (!c.established) {
    c.established = Handshake(c, frame);
    return c.established;
  }
  if (loop_.commander() == c.id) last_heard_ = Clock::now();
  try {
    return HandleFrame(c, frame);
  } catch (const TransferError& e) {
    SendError(c, frame.sequence, kProtocolError, e.what());
    return false;
  }
}

bool SiteServer::Handshake(Connection& c, const Frame& frame) {
  const int auth = static_cast<int>(ErrorCode::kAuth);
  try {
    if (frame.type != MessageType::kHello) {
      throw TransferError(fmt::format("got {} before HELLO",
                                      MessageTypeName(static_cast<std::uint16_t>(frame.type))));
    }
    const HelloMessage hello = DecodeHello(frame);
    CheckRunTag(hello.client_name);
    const auto now = Clock::now();
    if (const auto verdict = auth_.Check(c.peer, now); verdict != AuthThrottle::Verdict::kAllowed) {
      SendError(c, frame.sequence, auth, AuthThrottle::RefusalText(verdict, c.peer));
      return false;
    }
    if (!TokensEqual(hello.token, options_.token)) {
      auth_.RecordFailure(c.peer, now);
      SendError(c, frame.sequence, auth,
                "wrong or missing token: the coordinator's token does not match the site's "
                "(--token-file / HYBRIDTEST_BENCH_TOKEN)");
      return false;
    }
    auth_.RecordSuccess(c.peer);
    sessions_[c.id].run = hello.client_name;
    WelcomeMessage welcome;
    welcome.description = fmt::format("site {}: {}", options_.name, bench_.Describe());
    welcome.units = units_;
    welcome.limits = gate_.monitor(0).limits();
    welcome.heartbeat_timeout = options_.watchdog;
    welcome.actuators = bench_.num_actuators();
    Log(fmt::format("coordinator run {} connected from {}", hello.client_name, c.peer));
    return Send(c, EncodeWelcome(frame.sequence, welcome));
  } catch (const TransferError& e) {
    SendError(c, frame.sequence, kProtocolError, fmt::format("expected HELLO: {}", e.what()));
    return false;
  }
}

std::optional<SiteServer::Verdict> SiteServer::Claim(Connection& c) {
  if (loop_.Claim(c.id)) return std::nullopt;
  // The same run on a new connection: the coordinator reconnected; its old link is stale.
  const int old = loop_.commander();
  if (sessions_.count(old) != 0 && sessions_[old].run == sessions_[c.id].run) {
    loop_.Release(old);
    Log(fmt::format("run {} reconnected (connection {} replaces {})", sessions_[c.id].run, c.id,
                    old));
    if (loop_.Claim(c.id)) return std::nullopt;
  }
  Verdict busy;
  busy.code = static_cast<int>(ErrorCode::kBusy);
  busy.text = fmt::format("another coordinator (run {}) commands this site",
                          sessions_.count(old) != 0 ? sessions_[old].run : "?");
  return busy;
}

bool SiteServer::Answer(Connection& c, std::uint32_t sequence, const Verdict& v) {
  switch (v.kind) {
    case Verdict::Kind::kAccept:
      return Send(c, EncodeAccept(sequence, v.id));
    case Verdict::Kind::kRefuse:
      return Send(c, EncodeRefuse(sequence, v.refusal));
    case Verdict::Kind::kResult:
      return Send(c, EncodeResult(sequence, v.result));
    case Verdict::Kind::kError:
      break;
  }
  SendError(c, sequence, v.code, v.text);
  return v.keep;
}

bool SiteServer::HandleFrame(Connection& c, const Frame& frame) {
  switch (frame.type) {
    case MessageType::kPropose:
      return Answer(c, frame.sequence, Propose(c, DecodePropose(frame)));
    case MessageType::kExecute:
      return Answer(c, frame.sequence,
                    Execute(c, DecodeIdOnly(frame, MessageType::kExecute)));
    case MessageType::kQuery:
      return Answer(c, frame.sequence, Query(DecodeIdOnly(frame, MessageType::kQuery)));
    case MessageType::kHeartbeat:
      DecodeEmpty(frame, MessageType::kHeartbeat);
      return Send(c, EncodeEmpty(MessageType::kHeartbeatAck, frame.sequence));
    case MessageType::kHold:
      DecodeEmpty(frame, MessageType::kHold);
      if (const auto busy = Claim(c)) return Answer(c, frame.sequence, *busy);
      last_heard_ = Clock::now();
      HoldBench("the coordinator asked for HOLD");
      return Send(c, EncodeEmpty(MessageType::kHoldAck, frame.sequence));
    case MessageType::kBye:
      if (loop_.commander() == 0 || loop_.commander() == c.id) {
        HoldBench("the coordinator said BYE");
      }
      Send(c, EncodeEmpty(MessageType::kBye, frame.sequence));
      return false;
    default:
      SendError(c, frame.sequence, kProtocolError,
                fmt::format("unexpected {} frame at a site",
                            MessageTypeName(static_cast<std::uint16_t>(frame.type))));
      return false;
  }
}

SiteServer::Verdict SiteServer::Propose(Connection& c, Proposal p) {
  Verdict v;
  v.id = p.id;
  if (static_cast<int>(p.targets.size()) != gate_.size()) {
    v.code = kProtocolError;
    v.text = fmt::format("PROPOSE of {} with {} targets for a site of {} actuators", p.id.Text(),
                         p.targets.size(), gate_.size());
    v.keep = false;
    return v;
  }
  if (auto busy = Claim(c)) return std::move(*busy);
  last_heard_ = Clock::now();
  v.kind = Verdict::Kind::kAccept;
  // Executed already, or the proposal accepted already: the same answer again.
  if (journal_.Find(p.id) != nullptr ||
      (accepted_ && accepted_->id.SameKey(p.id) && accepted_->targets == p.targets)) {
    return v;
  }
  commands_m_.resize(p.targets.size());
  for (std::size_t k = 0; k < p.targets.size(); ++k) {
    commands_m_[k] = p.targets[k] * units_.metres_per_length_unit;
  }
  try {
    gate_.Vet(commands_m_, {p.id.step, p.id.stage});
  } catch (const SafetyStop& e) {
    ++refusals_;
    journal_.Proposed(p, "refuse:" + e.limit());
    Log(fmt::format("refused {}: {}", p.id.Text(), e.what()));
    v.kind = Verdict::Kind::kRefuse;
    v.refusal = {p.id, e.limit(), e.value(), e.limit_value(), e.what()};
    return v;
  }
  journal_.Proposed(p, "accept");
  accepted_ = std::move(p);
  return v;
}

SiteServer::Verdict SiteServer::Execute(Connection& c, const TransactionId& id) {
  if (auto busy = Claim(c)) return std::move(*busy);
  last_heard_ = Clock::now();
  Verdict v;
  v.id = id;
  if (const auto* done = journal_.Find(id)) {  // at most once: the record answers
    Log(fmt::format("repeated EXECUTE of {}: answered from the record", id.Text()));
    v.kind = Verdict::Kind::kResult;
    v.result = {id, true, *done};
    return v;
  }
  if (!accepted_ || !accepted_->id.SameKey(id)) {
    v.code = kProtocolError;
    v.text = fmt::format("EXECUTE of {}: no accepted proposal of this id at this site (PROPOSE "
                         "it first); nothing moved", id.Text());
    return v;
  }
  try {
    gate_.MoveBench(bench_, accepted_->targets, {id.step, id.stage}, moves_, [&] {
      if (held_) {
        bench_.Activate();
        held_ = false;
      }
    });
  } catch (const SafetyStop& e) {
    HoldBench(fmt::format("safety stop in {} ({})", id.Text(), e.limit()));
    accepted_.reset();
    v.code = static_cast<int>(ErrorCode::kSafety);
    v.text = e.what();
    return v;
  } catch (const Error& e) {
    HoldBench(fmt::format("bench failure in {}", id.Text()));
    v.code = static_cast<int>(ErrorCode::kBench);
    v.text = fmt::format("the bench failed to execute {}: {}", id.Text(), e.what());
    v.keep = false;
    return v;
  }
  std::vector<Measurement> measured;
  for (const auto& m : moves_) measured.push_back(m.raw);
  journal_.Executed(id, measured);
  ++executed_;
  accepted_.reset();
  v.kind = Verdict::Kind::kResult;
  v.result = {id, false, std::move(measured)};
  return v;
}

SiteServer::Verdict SiteServer::Query(const TransactionId& id) const {
  Verdict v;
  v.id = id;
  if (const auto* done = journal_.Find(id)) {
    v.kind = Verdict::Kind::kResult;
    v.result = {id, true, *done};
    return v;
  }
  v.code = kProtocolError;
  v.text = fmt::format("QUERY of {}: this site has not executed it", id.Text());
  return v;
}

void SiteServer::Closed(Connection& c, const ServerLoop::Closing& closing) {
  if (c.established && closing.commander && !held_) {
    HoldBench(fmt::format("the coordinator's connection ended ({})", closing.why));
  }
  sessions_.erase(c.id);
}

}  // namespace hybridtest::transfer::site
