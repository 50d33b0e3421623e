// The Session's seam and row sink (internal to the runner: only session*.cc include it).
//
// The seam is where the scheme's slot displacements meet the substructures: every substructure
// is tried at its slots' displacements (m slots in its own order: gathered, tried, scattered),
// then the observers see the trial. With two physical substructures or more, or any that is a
// site (docs/multi-site.md), a trial has two phases: every substructure proposes its move (its
// safety gate checks it; a site decides on it), every verdict is collected, and only then does
// any move (the sites' in parallel): a refusal anywhere moves nothing, and Session::Fail holds
// every actuator. A site that loses its link has the other sites hold while it waits.
#pragma once

#include <Eigen/Core>

#include "hybridtest/runner/session.h"
#include "hybridtest/schemes/hybrid_scheme.h"

namespace hybridtest::runner {

class Session::Seam final : public schemes::SubstructureSeam {
 public:
  explicit Seam(Session& session);
  void Trial(const schemes::TrialPoint& at, const Eigen::VectorXd& d,
             Eigen::Ref<Eigen::VectorXd> r) override;

 private:
  Session& session_;
  bool two_phase_ = false;
};

// A scheme's intermediate rows (no specimen sample belongs to them).
class Session::Rows final : public schemes::RowSink {
 public:
  explicit Rows(Session& session) : session_(session) {}
  void Row(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& r) override;

 private:
  Session& session_;
};

}  // namespace hybridtest::runner
