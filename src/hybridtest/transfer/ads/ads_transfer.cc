// See ads_transfer.h: construction, the checks before anything moves, the lifecycle
// (Activate, Hold, Deactivate) and reads without a move. Execute and Probe are in
// ads_execute.cc.
#include "hybridtest/transfer/ads/ads_transfer.h"

#include <fmt/core.h>

#include <cmath>
#include <thread>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/safety.h"

namespace hybridtest::transfer::ads {
namespace {

using Clock = std::chrono::steady_clock;

// What the exception being handled says.
std::string WhatFailed() {
  try {
    throw;
  } catch (const std::exception& e) {
    return e.what();
  } catch (...) {
    return "an unknown error";
  }
}

// The roles read by every poll, in the order of a Readout.
constexpr Role kOutputs[] = {kPosition, kForce, kAck, kEnabled, kFault, kHolding};

}  // namespace

AdsTransfer::AdsTransfer(AdsOptions options) : options_(std::move(options)), link_(options_.endpoint) {
  AdsOptions& o = options_;
  if (o.profile.actuators < 1) {
    throw ConfigError(fmt::format("ads transfer: actuators = {}: expected 1 or more",
                                  o.profile.actuators));
  }
  for (std::size_t r = 0; r < kNumRoles; ++r) {
    if (o.profile.symbols[r].empty()) {
      throw ConfigError(fmt::format("ads transfer: symbols.{} is empty: give the PLC variable's "
                                    "name, e.g. {}", RoleKey(static_cast<Role>(r)),
                                    DefaultSymbol(static_cast<Role>(r))));
    }
  }
  // The heartbeat starts from the clock: almost surely not where an earlier client (the run
  // this one resumes) left it, so that its first write is a change the watchdog sees.
  heartbeat_ = static_cast<std::uint32_t>(Clock::now().time_since_epoch().count());
  move_ = AcknowledgedMove(
      o, o.profile.units,
      std::vector<std::uint64_t>(static_cast<std::size_t>(o.profile.actuators), 1ULL << 32),
      true, "ads transfer");
}

AdsTransfer::~AdsTransfer() {
  ReleaseHandles();
  link_.Close();
}

std::string AdsTransfer::Subject() const { return "the PLC at " + link_.Where(); }

std::string AdsTransfer::Describe() const {
  const AdsProfile& p = options_.profile;
  return fmt::format("TwinCAT PLC over ADS at {}:{} (AmsNetId {}:{}; {}, {}; {} actuator{}; "
                     "command {}, ack {})", options_.endpoint.host, options_.endpoint.tcp_port,
                     FormatAmsNetId(options_.endpoint.target.net_id),
                     options_.endpoint.target.port, p.units.length_name, p.units.force_name,
                     p.actuators, p.actuators == 1 ? "" : "s", p.symbols[kCommand],
                     p.symbols[kAck]);
}

std::string AdsTransfer::Describe(const Readout& r) const {
  const AdsProfile& p = options_.profile;
  const auto list = [](const std::vector<double>& v) {
    std::string text;
    for (double x : v) text += (text.empty() ? "" : ", ") + fmt::format("{}", x);
    return v.size() == 1 ? text : "[" + text + "]";
  };
  return fmt::format("{} = {}, {} = {} {}, {} = {} {}, {} = {}, {} = {}, {} = {}",
                     p.symbols[kAck], r.ack, p.symbols[kPosition], list(r.position),
                     p.units.length_name, p.symbols[kForce], list(r.force), p.units.force_name,
                     p.symbols[kEnabled], r.enabled, p.symbols[kFault], r.fault,
                     p.symbols[kHolding], r.holding);
}

void AdsTransfer::CheckSymbol(Role role) {
  const std::string& name = options_.profile.symbols[role];
  const ExpectedSymbol want = Expected(role, options_.profile.actuators);
  const std::string key = fmt::format("transfer.symbols.{}", RoleKey(role));
  SymbolInfo info;
  try {
    info = DecodeSymbolInfo(link_.ReadWrite(kGroupSymbolInfoByName, 0, 0xFFFF, NameData(name),
                                            options_.response_timeout,
                                            "the symbol info of " + name));
  } catch (const AdsError& e) {
    if (e.code() != kErrSymbolNotFound) throw;
    // The PLC project and the run config disagree: the user's configuration (exit 2).
    throw ConfigError(fmt::format(
        "{} has no symbol {} ({}, {}; ADS error {}): declare `{} : {};` in the PLC project "
        "(docs/ads.md, \"The profile\") and activate it, or set {} to the variable's name",
        Subject(), name, RoleKey(role), want.type, AdsErrorName(e.code()),
        name.substr(name.find('.') + 1), want.type, key));
  }
  if (NormaliseTypeName(info.type) != NormaliseTypeName(want.type) || info.size != want.size) {
    throw ConfigError(fmt::format(
        "{}: symbol {} is {} ({} bytes), expected {} ({} bytes) for the {} of {} actuator{}: "
        "declare it as `{} : {};` in the PLC (docs/ads.md), or name a variable of that type in "
        "{}; nothing was moved", Subject(), name, info.type, info.size, want.type, want.size,
        RoleKey(role), options_.profile.actuators, options_.profile.actuators == 1 ? "" : "s",
        name.substr(name.find('.') + 1), want.type, key));
  }
}

void AdsTransfer::Connect() {
  link_.Connect(options_.connect_timeout);
  handles_.clear();
  try {
    // 1. The PLC must run its program.
    const StateResponse state = link_.ReadState(options_.response_timeout);
    if (state.ads_state != kStateRun) {
      throw TransferError(fmt::format(
          "{} is in {} (ADS state {}), not RUN: nothing was moved. Start the PLC (TwinCAT: "
          "activate the configuration in Run mode, then Login and Start the PLC program)",
          Subject(), AdsStateName(state.ads_state), state.ads_state));
    }
    // 2. Every symbol exists with the profile's type and size; 3. a handle for each.
    for (std::size_t r = 0; r < kNumRoles; ++r) CheckSymbol(static_cast<Role>(r));
    for (std::size_t r = 0; r < kNumRoles; ++r) {
      const std::string& name = options_.profile.symbols[r];
      const HandleAnswer a = DecodeHandleAnswer(link_.ReadWrite(
          kGroupHandleByName, 0, 4, NameData(name), options_.response_timeout,
          "a handle for " + name));
      handles_.push_back(a.handle);
    }
  } catch (...) {
    ReleaseHandles();
    link_.Close();
    throw;
  }
}

void AdsTransfer::ReleaseHandles() noexcept {
  if (link_.is_open()) {
    for (std::uint32_t handle : handles_) {
      try {
        link_.Write(kGroupReleaseHandle, 0, EncodeUdint(handle), options_.hold_timeout,
                    "the release of a handle");
      } catch (...) {
        break;  // the link is gone or the PLC refuses: its handles die with the connection
      }
    }
  }
  handles_.clear();
}

void AdsTransfer::WriteSymbols(std::span<const Role> roles,
                               std::span<const std::vector<std::uint8_t>> values, double timeout,
                               const std::string& what) {
  std::vector<SubRequest> items;
  for (std::size_t i = 0; i < roles.size(); ++i) {
    items.push_back({kGroupValueByHandle, handles_.at(roles[i]),
                     static_cast<std::uint32_t>(values[i].size()), values[i]});
  }
  const std::vector<std::uint32_t> results = link_.SumWrite(items, timeout, what);
  for (std::size_t i = 0; i < roles.size(); ++i) {
    if (results[i] != 0) {
      throw AdsError(fmt::format("{} refused the write of {} ({}): ADS error {}", Subject(),
                                 options_.profile.symbols[roles[i]], what,
                                 AdsErrorName(results[i])), results[i]);
    }
  }
}

AdsTransfer::Readout AdsTransfer::ReadOutputs(const std::string& what) {
  if (handles_.size() != kNumRoles) {
    throw TransferError(fmt::format("{}: not connected for {}; call Activate() first", Subject(),
                                    what));
  }
  std::vector<SubRequest> items;
  for (Role role : kOutputs) {
    items.push_back({kGroupValueByHandle, handles_[role],
                     Expected(role, options_.profile.actuators).size, {}});
  }
  const std::vector<DataResponse> answers = link_.SumRead(items, options_.response_timeout, what);
  for (std::size_t i = 0; i < answers.size(); ++i) {
    if (answers[i].result != 0) {
      throw AdsError(fmt::format("{} refused the read of {} ({}): ADS error {}", Subject(),
                                 options_.profile.symbols[kOutputs[i]], what,
                                 AdsErrorName(answers[i].result)), answers[i].result);
    }
  }
  Readout r;
  r.position = DecodeReals(answers[0].data);
  r.force = DecodeReals(answers[1].data);
  r.ack = DecodeUdint(answers[2].data);
  r.enabled = DecodeBool(answers[3].data);
  r.fault = DecodeBool(answers[4].data);
  r.holding = DecodeBool(answers[5].data);
  return r;
}

void AdsTransfer::HoldAndFail(const std::string& message) {
  Hold();
  throw TransferError(message);
}

void AdsTransfer::CheckFault(const Readout& r, const std::string& during) {
  if (!r.fault) return;
  HoldAndFail(fmt::format("{} reports a fault ({} = TRUE) {}: {}; {} was set (every actuator "
                          "holds). Clear the fault at the PLC before resuming", Subject(),
                          options_.profile.symbols[kFault], during, Describe(r),
                          options_.profile.symbols[kHold]));
}

double AdsTransfer::WallSinceActivate() const {
  return std::chrono::duration<double>(Clock::now() - activated_at_).count();
}

void AdsTransfer::Activate() {
  if (!link_.is_open()) Connect();
  const AdsProfile& p = options_.profile;
  Readout r = ReadOutputs("the state before enabling");
  CheckFault(r, "before the test starts");
  // nCommandSeq := nAckSeq with the release: a command sent before a hold (and not
  // acknowledged) is never executed after it.
  const Role roles[] = {kSequence, kHeartbeat, kHold, kEnable};
  const std::vector<std::uint8_t> values[] = {EncodeUdint(r.ack), NextHeartbeat(),
                                              EncodeBool(false), EncodeBool(true)};
  WriteSymbols(roles, values, options_.response_timeout, "release the hold and enable");
  // Wait until the PLC shows enabled and not holding.
  const auto deadline = Clock::now() + std::chrono::duration<double>(options_.ack_timeout);
  for (;;) {
    r = ReadOutputs("the status after enabling");
    CheckFault(r, "while enabling");
    if (r.enabled && !r.holding) break;
    if (Clock::now() >= deadline) {
      HoldAndFail(fmt::format("{} did not report {} = TRUE and {} = FALSE within {} s after "
                              "{} was set: {}", Subject(), p.symbols[kEnabled], p.symbols[kHolding],
                              options_.ack_timeout, p.symbols[kEnable], Describe(r)));
    }
    BeatWhileWaiting();
    std::this_thread::sleep_for(std::chrono::duration<double>(options_.poll_interval));
  }
  for (double x : r.position) {
    if (!std::isfinite(x)) {
      HoldAndFail(fmt::format("{} reports a position that is not a number: {}", Subject(),
                              Describe(r)));
    }
  }
  if (!clock_started_) {
    clock_started_ = true;
    activated_at_ = Clock::now();
  }
  move_.Start(std::vector<std::uint64_t>(r.position.size(), r.ack));
  read_failure_.clear();
  active_ = true;
}

void AdsTransfer::Hold() noexcept {
  active_ = false;
  if (!link_.is_open() || handles_.size() != kNumRoles) return;
  try {
    link_.Write(kGroupValueByHandle, handles_[kHold], EncodeBool(true), options_.hold_timeout,
                "the hold");
  } catch (...) {
    // Best effort: a hold that did not get through drops the connection (link_ closed it on a
    // timeout); the PLC must hold when its client goes away.
    link_.Close();
  }
}

void AdsTransfer::Deactivate() {
  if (!link_.is_open()) return;
  active_ = false;
  try {
    if (handles_.size() == kNumRoles) {
      const Role roles[] = {kHold, kEnable};
      const std::vector<std::uint8_t> values[] = {EncodeBool(true), EncodeBool(false)};
      WriteSymbols(roles, values, options_.response_timeout, "hold and disable");
    }
  } catch (...) {
    link_.Close();
    throw;
  }
  ReleaseHandles();
  link_.Close();
}

std::optional<std::vector<Measurement>> AdsTransfer::ReadAll() {
  try {
    BeatIfDue();
    const Readout r = ReadOutputs("a read without moving");
    std::string problem;
    if (r.fault) problem = "reports a fault (" + options_.profile.symbols[kFault] + ")";
    else if (!r.enabled) problem = "does not report the drive enabled (" + options_.profile.symbols[kEnabled] + ")";
    else if (r.holding) problem = "reports holding (" + options_.profile.symbols[kHolding] + ")";
    for (std::size_t k = 0; k < r.position.size() && problem.empty(); ++k) {
      if (!std::isfinite(r.position[k]) || !std::isfinite(r.force[k])) {
        problem = fmt::format("reports a position or force of actuator {} that is not a number",
                              k + 1);
      }
    }
    if (!problem.empty()) {
      read_failure_ = fmt::format("{} {}: {}", Subject(), problem, Describe(r));
      return std::nullopt;
    }
    std::vector<Measurement> out;
    const double lab_time = clock_started_ ? WallSinceActivate() : 0.0;
    for (std::size_t k = 0; k < r.position.size(); ++k) {
      out.push_back(Measurement{r.position[k], r.force[k], lab_time});
    }
    read_failure_.clear();
    return out;
  } catch (...) {
    try {
      read_failure_ = WhatFailed();
    } catch (...) {  // no memory for the message: Execute refuses on the one below
      read_failure_.clear();
    }
  }
  if (read_failure_.empty()) read_failure_ = "the position could not be read";
  return std::nullopt;
}

}  // namespace hybridtest::transfer::ads
