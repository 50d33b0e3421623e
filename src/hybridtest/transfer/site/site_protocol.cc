// See site_protocol.h.
#include "hybridtest/transfer/site/site_protocol.h"

#include <fmt/core.h>

#include "hybridtest/common/error.h"
#include "hybridtest/common/text.h"

namespace hybridtest::transfer::site {
namespace {

void PutTransactionId(ByteWriter& w, const TransactionId& id) {
  CheckRunTag(id.run);
  const auto step = static_cast<std::uint64_t>(static_cast<std::int64_t>(id.step));
  w.Str(id.run);
  w.U32(id.seq);
  w.U32(static_cast<std::uint32_t>(step >> 32));
  w.U32(static_cast<std::uint32_t>(step & 0xFFFFFFFFu));
  w.U32(static_cast<std::uint32_t>(static_cast<std::int32_t>(id.stage)));
  w.U32(static_cast<std::uint32_t>(static_cast<std::int32_t>(id.attempt)));
}

TransactionId GetTransactionId(ByteReader& r) {
  TransactionId id;
  id.run = r.Str("run");
  CheckRunTag(id.run);
  id.seq = r.U32("seq");
  const std::uint64_t hi = r.U32("step_hi");
  const std::uint64_t lo = r.U32("step_lo");
  id.step = static_cast<long>(static_cast<std::int64_t>((hi << 32) | lo));
  id.stage = static_cast<std::int32_t>(r.U32("stage"));
  id.attempt = static_cast<std::int32_t>(r.U32("attempt"));
  return id;
}

void ExpectSiteMessage(const Frame& frame, MessageType type) {
  if (frame.type != type) {
    throw TransferError(fmt::format("expected {}, got {}",
                                    MessageTypeName(static_cast<std::uint16_t>(type)),
                                    MessageTypeName(static_cast<std::uint16_t>(frame.type))));
  }
}

std::uint16_t SiteActuatorCount(std::size_t n, const char* what) {
  if (n == 0 || n > 1024) {
    throw TransferError(fmt::format("{} with {} actuators: expected 1 to 1024", what, n));
  }
  return static_cast<std::uint16_t>(n);
}

}  // namespace

void CheckRunTag(const std::string& run) {
  bool ok = !run.empty() && run.size() <= kMaxRunTagBytes;
  for (char c : run) {
    ok = ok && ((c >= '0' && c <= '9') || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                c == '-' || c == '_' || c == '.');
  }
  if (!ok) {
    throw TransferError(fmt::format("run tag '{}': expected 1 to {} letters, digits, '-', '_' "
                                    "or '.'", Printable(run), kMaxRunTagBytes));
  }
}

std::string TransactionId::Text() const {
  return fmt::format("{}/{} (step {}, stage {}, attempt {})", run, seq, step, stage, attempt);
}

Frame EncodePropose(std::uint32_t sequence, const Proposal& p) {
  ByteWriter w;
  PutTransactionId(w, p.id);
  w.U16(SiteActuatorCount(p.targets.size(), "PROPOSE"));
  for (double t : p.targets) w.F64(t);
  return {MessageType::kPropose, sequence, w.Take()};
}

Frame EncodeAccept(std::uint32_t sequence, const TransactionId& id) {
  return EncodeIdOnly(MessageType::kAccept, sequence, id);
}

Frame EncodeRefuse(std::uint32_t sequence, const Refusal& r) {
  ByteWriter w;
  PutTransactionId(w, r.id);
  w.Str(r.limit);
  w.F64(r.value);
  w.F64(r.limit_value);
  w.Str(r.reason.size() > 4000 ? r.reason.substr(0, 4000) : r.reason);
  return {MessageType::kRefuse, sequence, w.Take()};
}

Frame EncodeIdOnly(MessageType type, std::uint32_t sequence, const TransactionId& id) {
  ByteWriter w;
  PutTransactionId(w, id);
  return {type, sequence, w.Take()};
}

Frame EncodeResult(std::uint32_t sequence, const Result& r) {
  ByteWriter w;
  PutTransactionId(w, r.id);
  w.U16(r.replayed ? 1 : 0);
  w.U16(SiteActuatorCount(r.measurements.size(), "RESULT"));
  for (const auto& m : r.measurements) {
    w.F64(m.position);
    w.F64(m.force);
    w.F64(m.lab_time);
    w.F64(static_cast<double>(m.force_reversals));
  }
  return {MessageType::kResult, sequence, w.Take()};
}

Proposal DecodePropose(const Frame& frame) {
  ExpectSiteMessage(frame, MessageType::kPropose);
  ByteReader r(frame.payload, "PROPOSE payload");
  Proposal p;
  p.id = GetTransactionId(r);
  const std::uint16_t n = r.U16("n");
  SiteActuatorCount(n, "PROPOSE");
  for (std::uint16_t k = 0; k < n; ++k) p.targets.push_back(r.F64("target"));
  r.Finish();
  return p;
}

TransactionId DecodeAccept(const Frame& frame) {
  return DecodeIdOnly(frame, MessageType::kAccept);
}

Refusal DecodeRefuse(const Frame& frame) {
  ExpectSiteMessage(frame, MessageType::kRefuse);
  ByteReader r(frame.payload, "REFUSE payload");
  Refusal x;
  x.id = GetTransactionId(r);
  x.limit = r.Str("limit");
  x.value = r.F64("value");
  x.limit_value = r.F64("limit_value");
  x.reason = r.Str("reason");
  r.Finish();
  return x;
}

TransactionId DecodeIdOnly(const Frame& frame, MessageType expected) {
  ExpectSiteMessage(frame, expected);
  ByteReader r(frame.payload, MessageTypeName(static_cast<std::uint16_t>(expected)) + " payload");
  TransactionId id = GetTransactionId(r);
  r.Finish();
  return id;
}

Result DecodeResult(const Frame& frame) {
  ExpectSiteMessage(frame, MessageType::kResult);
  ByteReader r(frame.payload, "RESULT payload");
  Result x;
  x.id = GetTransactionId(r);
  x.replayed = r.U16("replayed") != 0;
  const std::uint16_t n = r.U16("n");
  SiteActuatorCount(n, "RESULT");
  for (std::uint16_t k = 0; k < n; ++k) {
    Measurement m;
    m.position = r.F64("position");
    m.force = r.F64("force");
    m.lab_time = r.F64("lab_time");
    const double reversals = r.F64("force_reversals");
    m.force_reversals = reversals >= 0.0 && reversals < 1e15 ? static_cast<long>(reversals) : 0;
    x.measurements.push_back(m);
  }
  r.Finish();
  return x;
}

}  // namespace hybridtest::transfer::site
