// A site goes through the run's one start check (issue 45 item 1; docs/safety.md, "The start
// of a run"; docs/multi-site.md): before the first command, the coordinator reads where the
// site's actuators are (a QUERY of the measurement now, nothing moves) and compares it with
// the first command; beyond max_increment the run refuses before anything moves, naming the
// actuator, its position and p0, or with `start: ramp` ramps there and finishes.
#include <gtest/gtest.h>

#include <string>

#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/runner/session.h"
#include "runner/multi_site_support.h"
#include "support/temp_dir.h"

namespace hybridtest::runner {
namespace {

using testing_site::Sites;

// The sidecar's statistics.start of a run (what `run` writes beside the journal).
class StartRecorder final : public SessionObserver {
 public:
  void OnStop(const StopEvent& e) override {
    start = e.statistics.value("start", nlohmann::json());
  }
  nlohmann::json start;
};

struct StartOutcome {
  StepResult result;
  nlohmann::json start;
};

StartOutcome RunRotor(Sites& sites, bool ramp) {
  io::RunSpec spec = io::LoadRunSpec(testing_site::kExample + "multi-site.yaml");
  testing_site::SetDuration(spec, 0.02);
  spec.start_ramp = ramp;
  spec.output.files = false;
  spec.quiet = true;
  sites.Point(spec);
  Session session(std::move(spec));
  StartRecorder recorder;
  session.AddObserver(recorder);
  StartOutcome o{session.Run(), {}};
  o.start = recorder.start;
  return o;
}

TEST(MultiSiteStart, ASiteAwayFromP0RefusesTheRunBeforeAnythingMoves) {
  const auto dir = test_support::FreshTempDir("multi-site-start-refuse");
  // Blade 2's bench sits at 35 mm; p0 = 20 mm and max_increment = 5 mm.
  Sites sites(dir, {}, {{1, 35.0}});
  const StartOutcome o = RunRotor(sites, false);
  ASSERT_EQ(o.result.status, SessionStatus::kStopped) << o.result.reason;
  const std::string& why = o.result.reason;
  EXPECT_NE(why.find("r2"), std::string::npos) << why;
  EXPECT_NE(why.find("the actuator is at 0.035 m (35 mm)"), std::string::npos) << why;
  EXPECT_NE(why.find("p0 = 0.02 m (20 mm)"), std::string::npos) << why;
  EXPECT_NE(why.find("start: ramp"), std::string::npos) << why;
  for (int s = 0; s < 3; ++s) EXPECT_EQ(sites.server(s).executed(), 0) << "site " << s << " moved";
}

TEST(MultiSiteStart, ASiteAwayFromP0RampsWithStartRampAndFinishes) {
  const auto dir = test_support::FreshTempDir("multi-site-start-ramp");
  Sites sites(dir, {}, {{1, 35.0}});
  const StartOutcome o = RunRotor(sites, true);
  ASSERT_EQ(o.result.status, SessionStatus::kFinished) << o.result.reason;
  ASSERT_TRUE(o.start.is_array() && o.start.size() == 3) << o.start;
  for (int s = 0; s < 3; ++s) {
    const nlohmann::json& r = o.start[static_cast<std::size_t>(s)];
    EXPECT_EQ(r["read"], true) << r;  // every site was read, none "cannot read"
    // 15 mm in moves within 5 mm: at least three for blade 2; none for the others.
    if (s == 1) {
      EXPECT_GE(r["ramp_moves"].get<int>(), 3) << r;
      EXPECT_NEAR(r["actuators"][0]["read_position_m"].get<double>(), 0.035, 1e-12) << r;
    } else {
      EXPECT_EQ(r["ramp_moves"].get<int>(), 0) << r;
    }
  }
  // Blade 2's site made the ramp's moves on top of the run's: 20 steps of Heun and the first.
  EXPECT_EQ(sites.server(0).executed(), 2 * 20 + 1);
  EXPECT_GE(sites.server(1).executed(), 2 * 20 + 1 + 3);
}

}  // namespace
}  // namespace hybridtest::runner
