// Steps a run from C++: compiles a run config once, prints every 1,000th commit from an
// observer, steps to the end, then prints the final state (to the last bit) and the statistics.
//   step_a_session examples/rotor/dummy.yaml
#include <cstdio>
#include <exception>
#include <utility>

#include <hybridtest/hybridtest.h>

namespace rn = hybridtest::runner;

// An observer sees every committed point: step n, time t [s], x = [q; u] (SI), forces r [N].
struct Printer : rn::SessionObserver {
  void OnCommit(const rn::CommitEvent& e) override {
    if (e.kind == rn::RowKind::kCommitted && e.step % 1000 == 0)
      std::printf("commit %ld: t = %g s, q1 = %g\n", e.step, e.t, e.x[0]);
  }
};

int main(int argc, char** argv) {
  if (argc != 2) return std::fprintf(stderr, "usage: step_a_session RUN.yaml\n"), 2;
  try {
    hybridtest::io::RunSpec spec = hybridtest::io::LoadRunSpec(argv[1]);  // YAML read once
    spec.output.files = false;  // in memory: no journal, no run state, no lock
    rn::Session session(std::move(spec));
    Printer printer;
    session.AddObserver(printer);
    rn::StepResult result = session.Initialize();  // the trial at x0, committed
    while (result.status == rn::SessionStatus::kWorking) result = session.Step();
    if (result.status != rn::SessionStatus::kFinished) {
      std::fprintf(stderr, "%s: %s\n", rn::StatusName(result.status), result.reason.c_str());
      return 1;
    }

    const hybridtest::schemes::CommittedPoint& last = session.committed();
    std::printf("final state at step %ld, t = %.17g s:\n", last.step, last.t);
    for (int i = 0; i < session.model().num_coordinates(); ++i)
      std::printf("  q%d = %.17g\n", i + 1, last.x[i]);
    const rn::RunStatistics& s = session.statistics();
    std::printf("statistics: %ld steps, %ld rows, %ld physical evaluations, sim time %g s, "
                "wall time %.3f s, lab time %g s\n", s.steps, s.rows, s.physical_evaluations,
                s.sim_time, s.wall_time, s.lab_time);
  } catch (const hybridtest::ConfigError& e) {
    return std::fprintf(stderr, "%s\n", e.what()), 2;
  } catch (const std::exception& e) {
    return std::fprintf(stderr, "%s\n", e.what()), 1;
  }
}
