// See session_seam.h.
#include "hybridtest/runner/session_seam.h"

#include "hybridtest/substructures/physical_substructure.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::runner {

Session::Seam::Seam(Session& session) : session_(session) {
  auto& subs = session_.subs_;
  int physical = 0;
  for (std::size_t s = 0; s < subs.size(); ++s) {
    transfer::TransferSystem* t = subs[s]->transfer_system();
    if (subs[s]->is_physical()) ++physical;
    if (t == nullptr || !t->two_phase()) continue;
    two_phase_ = true;
    // A site that loses its link holds the other sites while it waits for it.
    t->OnLinkLost([&subs, s] {
      for (std::size_t o = 0; o < subs.size(); ++o) {
        transfer::TransferSystem* other = subs[o]->transfer_system();
        if (o != s && other != nullptr && other->two_phase()) other->Hold();
      }
    });
  }
  two_phase_ = two_phase_ || physical > 1;
}

void Session::Seam::Trial(const schemes::TrialPoint& at, const Eigen::VectorXd& d,
                          Eigen::Ref<Eigen::VectorXd> r) {
  for (SessionObserver* o : session_.observers_) o->BeforeTrial(at);
  auto& subs = session_.subs_;
  auto& ds = session_.d_slots_;
  auto& rs = session_.r_slots_;
  const substructures::TrialContext context{at.step, at.stage, at.t};
  // The substructure's m slots, in its order: gathered, tried, scattered.
  const auto gather = [&](std::size_t s) {
    const auto& slots = session_.slot_of_[s];
    ds.resize(slots.size());
    for (std::size_t k = 0; k < slots.size(); ++k) ds[k] = d(slots[k]);
  };
  if (two_phase_) {
    for (std::size_t s = 0; s < subs.size(); ++s) {
      gather(s);
      subs[s]->Propose(ds, context);
    }
    for (auto& sub : subs) sub->AwaitVerdict();
    for (auto& sub : subs) sub->Release();
  }
  for (std::size_t s = 0; s < subs.size(); ++s) {
    const auto& slots = session_.slot_of_[s];
    gather(s);
    rs.resize(slots.size());
    subs[s]->Trial(ds, rs, context);
    for (std::size_t k = 0; k < slots.size(); ++k) r(slots[k]) = rs[k];
  }
  session_.PublishTrial(at, d, r);
}

void Session::Rows::Row(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& r) {
  session_.Publish(RowKind::kIntermediate, session_.stats_.steps, t, x, r);
}

}  // namespace hybridtest::runner
