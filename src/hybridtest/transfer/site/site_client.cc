// See site_client.h.
#include "hybridtest/transfer/site/site_client.h"

#include <fmt/core.h>
#include <unistd.h>

#include <algorithm>
#include <random>
#include <thread>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/safety.h"

namespace hybridtest::transfer::site {
namespace {

using SiteClock = std::chrono::steady_clock;

// One tag per coordinator process: its transactions' keys never meet another run's.
std::string ProcessRunTag() {
  static const std::string tag = [] {
    std::random_device device;
    const std::uint64_t r = (static_cast<std::uint64_t>(device()) << 32) ^ device();
    return fmt::format("r{:x}-{}", r, static_cast<long>(::getpid()));
  }();
  return tag;
}

}  // namespace

SiteClient::SiteClient(SiteClientOptions options) : options_(std::move(options)) {
  for (double t : {options_.connect_timeout, options_.propose_timeout, options_.execute_timeout,
                   options_.hold_timeout, options_.reconnect_wait}) {
    if (!(t > 0.0)) {
      throw ConfigError(fmt::format("{}: every time-out must be a positive time in seconds",
                                    options_.name));
    }
  }
  if (options_.run.empty()) options_.run = ProcessRunTag();
  try {
    CheckRunTag(options_.run);
  } catch (const TransferError& e) {
    throw ConfigError(fmt::format("{}: {}", options_.name, e.what()));
  }
}

SiteClient::~SiteClient() = default;

std::string SiteClient::Endpoint() const {
  return fmt::format("site {} at {}:{}", options_.name, options_.host, options_.port);
}

void SiteClient::Fail(const std::string& what) const { throw TransferError(what); }

bool SiteClient::SendFrame(const Frame& frame) {
  if (!socket_.is_open()) return false;
  const std::vector<std::uint8_t> bytes = EncodeFrame(frame);
  if (!SendAll(socket_.fd(), bytes, options_.connect_timeout)) {
    socket_.Close();
    return false;
  }
  bytes_sent_ += bytes.size();
  return true;
}

std::optional<Frame> SiteClient::Await(std::uint32_t sequence, double timeout) {
  if (const auto it = early_.find(sequence); it != early_.end()) {
    Frame f = std::move(it->second);
    early_.erase(it);
    return f;
  }
  const auto deadline = SiteClock::now() + std::chrono::duration<double>(timeout);
  loss_ = socket_.is_open() ? fmt::format("no answer within {} s", timeout) : "not connected";
  while (socket_.is_open()) {
    const double left = std::chrono::duration<double>(deadline - SiteClock::now()).count();
    if (left <= 0.0) break;
    Frame frame;
    ReadStatus status;
    try {
      status = ReadFrame(socket_.fd(), left, frame);
    } catch (const TransferError& e) {
      status = ReadStatus::kClosed;  // garbled: the link is not to be trusted
      loss_ = e.what();
    }
    if (status == ReadStatus::kClosed && loss_.rfind("no answer", 0) == 0) {
      loss_ = "the connection closed";
    }
    if (status != ReadStatus::kFrame) break;
    bytes_received_ += kFrameHeaderSize + frame.payload.size() + kFrameTrailerSize;
    if (frame.sequence == sequence) return frame;
    if (frame.sequence > sequence || early_.size() >= 8) break;  // out of order: not trusted
    early_[frame.sequence] = std::move(frame);
  }
  socket_.Close();
  return std::nullopt;
}

void SiteClient::Connect() {
  socket_ = ConnectTcp(options_.host, options_.port, options_.connect_timeout);
  early_.clear();
  HelloMessage hello;
  hello.token = options_.token;
  hello.client_name = options_.run;
  const std::uint32_t sequence = next_sequence_++;
  if (!SendFrame(EncodeHello(sequence, hello))) Fail(Endpoint() + ": the HELLO was not sent");
  const auto reply = Await(sequence, options_.propose_timeout);
  if (!reply) Fail(Endpoint() + ": no WELCOME (the answer to HELLO)");
  if (reply->type == MessageType::kError) {
    socket_.Close();
    Fail(fmt::format("{} refused the coordinator: {}", Endpoint(), DecodeError(*reply).text));
  }
  WelcomeMessage welcome = DecodeWelcome(*reply);
  if (welcome.actuators != options_.actuators) {
    socket_.Close();
    throw ConfigError(fmt::format("{} moves {} actuators, the config's setup {}", Endpoint(),
                                  welcome.actuators, options_.actuators));
  }
  welcome_ = std::move(welcome);
}

void SiteClient::Activate() {
  if (socket_.is_open()) return;
  try {
    Connect();
  } catch (const TransferError& e) {
    throw TransferError(fmt::format("{} (is `hybridtest site` running there?)", e.what()));
  }
}

void SiteClient::Recover(const std::string& why) {
  socket_.Close();
  if (link_lost_) link_lost_();
  const auto deadline = SiteClock::now() + std::chrono::duration<double>(options_.reconnect_wait);
  double backoff = 0.1;  // [s]
  std::string last = why;
  while (SiteClock::now() < deadline) {
    try {
      Connect();
      ++reconnects_;
      return;
    } catch (const TransferError& e) {
      last = e.what();
    }
    const double left = std::chrono::duration<double>(deadline - SiteClock::now()).count();
    const double pause = std::min(backoff, std::max(left, 0.0));  // [s]
    std::this_thread::sleep_for(std::chrono::duration<double>(pause));
    backoff = std::min(2.0 * backoff, 2.0);
  }
  Fail(fmt::format("{}: the link was lost ({}) and did not come back within {} s "
                   "(reconnect_wait; last: {}); every site holds, every committed step is on "
                   "disk: `hybridtest resume` continues the run", Endpoint(), why,
                   options_.reconnect_wait, last));
}

void SiteClient::Resend() {
  propose_request_ = next_sequence_++;
  if (!SendFrame(EncodePropose(propose_request_, proposal_))) return;
  if (phase_ == Phase::kReleased) {
    execute_request_ = next_sequence_++;
    SendFrame(EncodeIdOnly(MessageType::kExecute, execute_request_, proposal_.id));
  }
}

void SiteClient::Propose(std::span<const double> commands, long step, int stage) {
  if (static_cast<int>(commands.size()) != options_.actuators) {
    Fail(fmt::format("{}: {} commands for {} actuators", Endpoint(), commands.size(),
                     options_.actuators));
  }
  if (!socket_.is_open()) Recover("not connected");
  attempt_ = step == last_step_ && stage == last_stage_ ? attempt_ + 1 : 0;
  last_step_ = step;
  last_stage_ = stage;
  proposal_.id = {options_.run, ++seq_, step, stage, attempt_};
  proposal_.targets.assign(commands.begin(), commands.end());
  phase_ = Phase::kProposed;
  propose_request_ = next_sequence_++;
  if (!SendFrame(EncodePropose(propose_request_, proposal_))) {
    Recover("PROPOSE not sent");
    Resend();
  }
}

void SiteClient::AwaitVerdict() {
  if (phase_ != Phase::kProposed) return;
  for (;;) {
    const auto reply = Await(propose_request_, options_.propose_timeout);
    if (!reply) {
      Recover(fmt::format("no verdict on {}: {}", proposal_.id.Text(), loss_));
      Resend();
      continue;
    }
    if (reply->type == MessageType::kAccept && DecodeAccept(*reply).SameKey(proposal_.id)) {
      phase_ = Phase::kAccepted;
      return;
    }
    phase_ = Phase::kIdle;
    if (reply->type == MessageType::kRefuse) {
      const Refusal r = DecodeRefuse(*reply);
      throw SafetyStop(r.limit, r.value, r.limit_value, proposal_.id.step, proposal_.id.stage, {},
                       fmt::format("{} refused {} (limit {}: {}); no site moved, every site "
                                   "holds. Change the site's limit or the test and resume",
                                   Endpoint(), proposal_.id.Text(), r.limit, r.reason));
    }
    if (reply->type == MessageType::kError) {
      Fail(fmt::format("{}: PROPOSE of {}: {}", Endpoint(), proposal_.id.Text(),
                       DecodeError(*reply).text));
    }
    Fail(fmt::format("{} answered {} to PROPOSE of {}", Endpoint(),
                     MessageTypeName(static_cast<std::uint16_t>(reply->type)),
                     proposal_.id.Text()));
  }
}

void SiteClient::Release() {
  if (phase_ != Phase::kAccepted) return;
  phase_ = Phase::kReleased;
  execute_request_ = next_sequence_++;
  if (!SendFrame(EncodeIdOnly(MessageType::kExecute, execute_request_, proposal_.id))) {
    Recover("EXECUTE not sent");
    Resend();
  }
}

void SiteClient::Execute(std::span<const double> commands, std::span<Measurement> out) {
  if (static_cast<int>(out.size()) != options_.actuators) {
    Fail(fmt::format("{}: {} measurements asked of {} actuators", Endpoint(), out.size(),
                     options_.actuators));
  }
  const bool same = phase_ != Phase::kIdle &&
                    std::equal(commands.begin(), commands.end(), proposal_.targets.begin(),
                               proposal_.targets.end());
  // A move nobody proposed (a ramp, a start walk, a resume): this site alone, both phases.
  if (!same) {
    Propose(commands, last_step_, -1);
    AwaitVerdict();
  }
  Release();
  for (;;) {
    const auto reply = Await(execute_request_, options_.execute_timeout);
    if (!reply) {
      Recover(fmt::format("no RESULT of {}: {}", proposal_.id.Text(), loss_));
      Resend();
      // The repeated PROPOSE is answered first (ACCEPT: proposed or executed already).
      if (const auto verdict = Await(propose_request_, options_.propose_timeout);
          !verdict || verdict->type != MessageType::kAccept) {
        phase_ = Phase::kIdle;
        Fail(fmt::format("{}: the site did not accept {} again after the link came back",
                         Endpoint(), proposal_.id.Text()));
      }
      continue;
    }
    phase_ = Phase::kIdle;
    if (reply->type == MessageType::kError) {
      const ErrorMessage e = DecodeError(*reply);
      if (e.code == ErrorCode::kSafety) {
        throw SafetyStop("site", 0.0, 0.0, proposal_.id.step, proposal_.id.stage, {},
                         fmt::format("{} stopped {}: {}", Endpoint(), proposal_.id.Text(),
                                     e.text));
      }
      Fail(fmt::format("{}: EXECUTE of {}: {}", Endpoint(), proposal_.id.Text(), e.text));
    }
    const Result r = DecodeResult(*reply);
    if (!r.id.SameKey(proposal_.id) ||
        static_cast<int>(r.measurements.size()) != options_.actuators) {
      Fail(fmt::format("{}: a RESULT of {} with {} measurements while {} was awaited", Endpoint(),
                       r.id.Text(), r.measurements.size(), proposal_.id.Text()));
    }
    std::copy(r.measurements.begin(), r.measurements.end(), out.begin());
    return;
  }
}

void SiteClient::Hold() noexcept {
  try {
    if (!socket_.is_open()) return;
    const std::uint32_t sequence = next_sequence_++;
    if (!SendFrame(EncodeEmpty(MessageType::kHold, sequence))) return;
    // The replies to a pending PROPOSE or EXECUTE come first; Await keeps them aside.
    if (!Await(sequence, options_.hold_timeout)) socket_.Close();
  } catch (...) {
    socket_.Close();  // the site holds on the disconnect
  }
}

void SiteClient::Deactivate() {
  if (!socket_.is_open()) return;
  Hold();
  const std::uint32_t sequence = next_sequence_++;
  if (SendFrame(EncodeEmpty(MessageType::kBye, sequence))) Await(sequence, options_.hold_timeout);
  socket_.Close();
}

std::optional<std::vector<Measurement>> SiteClient::ReadAll() {
  // Reading moves nothing, but it is an exchange on the link (QUERY of seq 0).
  if (!socket_.is_open() || !welcome_ || phase_ != Phase::kIdle) return std::nullopt;
  try {
    const std::uint32_t sequence = next_sequence_++;
    const TransactionId now{options_.run, kQueryNow, last_step_, -1, 0};
    if (!SendFrame(EncodeIdOnly(MessageType::kQuery, sequence, now))) return std::nullopt;
    // A lost link here is found again (and recovered) by the next move.
    const auto reply = Await(sequence, options_.propose_timeout);
    if (!reply || reply->type != MessageType::kResult) return std::nullopt;
    Result r = DecodeResult(*reply);
    if (r.id.seq != kQueryNow || static_cast<int>(r.measurements.size()) != options_.actuators) {
      return std::nullopt;
    }
    return std::move(r.measurements);
  } catch (const std::exception&) {
    socket_.Close();
    return std::nullopt;
  }
}

BenchUnits SiteClient::bench_units() const { return welcome_ ? welcome_->units : BenchUnits{}; }

std::string SiteClient::Describe() const {
  return welcome_ ? fmt::format("{} ({})", Endpoint(), welcome_->description) : Endpoint();
}

BenchAnnouncement SiteClient::Announce() const {
  if (!welcome_ || options_.actuators != 1) return {};
  return {{{std::nullopt, welcome_->limits}}, Endpoint()};
}

}  // namespace hybridtest::transfer::site
