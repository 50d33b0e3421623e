// See site_server.h.
#include "hybridtest/transfer/site/site_server.h"

#include <fmt/core.h>

#include <algorithm>
#include <filesystem>
#include <system_error>

#include "hybridtest/common/disk_room.h"
#include "hybridtest/common/error.h"
#include "hybridtest/common/text.h"
#include "hybridtest/transfer/frame_replies.h"
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
  if (o.journal_max_bytes == 0 || o.refusals_per_minute == 0) {
    throw ConfigError(fmt::format("site {}: journal_max_mb and refusals_per_minute must be "
                                  "positive", o.name));
  }
  if (!(o.watchdog > 0.0) || !(o.handshake_timeout > 0.0) || !(o.idle_timeout > 0.0)) {
    throw ConfigError(fmt::format("site {}: watchdog = {} s, handshake_timeout = {} s, "
                                  "idle_timeout = {} s: expected positive times", o.name,
                                  o.watchdog, o.handshake_timeout, o.idle_timeout));
  }
  return o.host;
}

// The journal up to its bound must fit on its disk (what it holds already counts): a site
// refuses to start rather than fill the disk, by the check a run's own journal passes.
const std::string& CheckedJournal(const SiteServerOptions& o) {
  if (o.journal.empty()) return o.journal;
  std::error_code ec;
  const std::uintmax_t held = std::filesystem::file_size(o.journal, ec);
  const std::uintmax_t to_come =
      o.journal_max_bytes - (ec ? 0 : std::min(held, o.journal_max_bytes));
  CheckFitsOnDisk(o.journal, to_come, fmt::format("site {}'s journal", o.name),
                  fmt::format(" up to its bound journal_max_mb = {:g}",
                              static_cast<double>(o.journal_max_bytes) / (1 << 20)),
                  "lower site.journal_max_mb in the site's config, free room on that disk, or "
                  "put the journal (site.journal) on a larger one");
  return o.journal;
}

constexpr int kProtocolError = static_cast<int>(ErrorCode::kProtocol);

}  // namespace

SiteServer::SiteServer(TransferSystem& bench, SiteServerOptions options)
    : bench_(bench),
      options_(std::move(options)),
      units_(bench.bench_units()),
      gate_(SiteLimits(options_, bench.num_actuators())),
      journal_(CheckedJournal(options_), options_.journal_max_bytes),
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

void SiteServer::HoldBench(const std::string& why, bool note) {
  bench_.Hold();
  if (!held_ || note) journal_.Held(why);  // a hold repeated is not journaled again
  if (!held_) ++holds_;
  held_ = true;
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
  loop_.Serve(stop_, [this] {
    // The watchdog: a silent coordinator leaves the bench holding.
    const double silent = std::chrono::duration<double>(Clock::now() - last_heard_).count();
    if (!held_ && loop_.commander() != 0 && silent > options_.watchdog) {
      HoldBench(fmt::format("watchdog: nothing from the coordinator for {} s", options_.watchdog));
    }
  });
  HoldBench("site stopping");
  bench_.Deactivate();
  Log("stopped");
}

bool SiteServer::Send(Connection& c, const Frame& frame) { return SendFrameOn(loop_, c, frame); }

void SiteServer::SendError(Connection& c, std::uint32_t sequence, int code,
                           const std::string& text) {
  SendErrorOn(loop_, c, sequence, {static_cast<ErrorCode>(code), "", 0.0, 0.0, text},
              [this](const std::string& line) { Log(line); });
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

void SiteServer::Closed(Connection& c, const ServerLoop::Closing& closing) {
  if (c.established && closing.commander && !held_) {
    HoldBench(fmt::format("the coordinator's connection ended ({})", closing.why));
  }
  sessions_.erase(c.id);
}

}  // namespace hybridtest::transfer::site
