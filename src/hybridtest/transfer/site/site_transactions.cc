// SiteServer's transaction rules (site_server.h), one for both codecs: who commands, a
// proposal vetted without moving, an id executed at most once, a query answered from the
// record or read now, and the journal's bound on refused proposals.
#include <fmt/core.h>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/protocol.h"
#include "hybridtest/transfer/site/site_server.h"

namespace hybridtest::transfer::site {
namespace {

constexpr int kSiteProtocolError = static_cast<int>(ErrorCode::kProtocol);

}  // namespace

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

SiteServer::Verdict SiteServer::Propose(Connection& c, Proposal p) {
  Verdict v;
  v.id = p.id;
  if (static_cast<int>(p.targets.size()) != gate_.size()) {
    v.code = kSiteProtocolError;
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
  if (!journal_.HasRoom(p.targets.size())) {  // bounded: refuse, hold, lose nothing executed
    ++refusals_;
    v.kind = Verdict::Kind::kRefuse;
    v.refusal = {p.id, "journal", static_cast<double>(journal_.bytes()),
                 static_cast<double>(journal_.max_bytes()),
                 fmt::format("the site's journal {} holds {} bytes, at its bound journal_max_mb "
                             "= {} MiB: this site accepts no more proposals (every executed "
                             "transaction is journaled). Raise journal_max_mb in the site's "
                             "config, or start the site on a new journal file, then resume",
                             options_.journal.empty() ? "(in memory)" : options_.journal,
                             journal_.bytes(),
                             static_cast<double>(journal_.max_bytes()) / (1 << 20))};
    if (!held_) Log(fmt::format("refused {}: {}", p.id.Text(), v.refusal.reason));
    HoldBench("the journal is full (journal_max_mb)");
    return v;
  }
  commands_m_.resize(p.targets.size());
  for (std::size_t k = 0; k < p.targets.size(); ++k) {
    commands_m_[k] = p.targets[k] * units_.metres_per_length_unit;
  }
  try {
    gate_.Vet(commands_m_, {p.id.step, p.id.stage});
  } catch (const SafetyStop& e) {
    RecordRefusal(p, e);
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
    v.code = kSiteProtocolError;
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
  if (id.seq == kQueryNow) {  // where the actuators are now, read without moving
    if (const auto now = bench_.ReadAll(); now && static_cast<int>(now->size()) == gate_.size()) {
      v.kind = Verdict::Kind::kResult;
      v.result = {id, false, *now};
      return v;
    }
    v.code = static_cast<int>(ErrorCode::kBench);
    v.text = fmt::format("QUERY of the current position: {} cannot read its position without "
                         "moving", bench_.Describe());
    return v;
  }
  if (const auto* done = journal_.Find(id)) {
    v.kind = Verdict::Kind::kResult;
    v.result = {id, true, *done};
    return v;
  }
  v.code = kSiteProtocolError;
  v.text = fmt::format("QUERY of {}: this site has not executed it", id.Text());
  return v;
}

void SiteServer::RecordRefusal(const Proposal& p, const SafetyStop& e) {
  ++refusals_;
  const auto now = Clock::now();
  refused_at_.push_back(now);
  while (refused_at_.size() > options_.refusals_per_minute + 1 ||
         now - refused_at_.front() > std::chrono::seconds(60)) {
    refused_at_.pop_front();
  }
  if (refused_at_.size() <= options_.refusals_per_minute) {
    flooded_ = false;
    journal_.Proposed(p, "refuse:" + e.limit());
    Log(fmt::format("refused {}: {}", p.id.Text(), e.what()));
    return;
  }
  if (flooded_) return;  // answered, neither journaled nor logged
  flooded_ = true;
  HoldBench(fmt::format("more than {} refused proposals within 60 s (refusals_per_minute): "
                        "further refusals are answered but not journaled until the rate falls",
                        options_.refusals_per_minute), true);
}

}  // namespace hybridtest::transfer::site
