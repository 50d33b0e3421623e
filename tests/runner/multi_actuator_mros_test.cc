// MR-OS on the two-actuator blade tip (examples/06_blade_two_actuators/mr-os.yaml): K0 (2 × 2)
// measured by ramping each actuator, the error of docs/lab-time.md against RK4 at 0.1 ms with
// the numerical Tᵀ K T; a K0 without its coupling is seen.
#include <gtest/gtest.h>

#include <filesystem>

#include "hybridtest/integrators/catalogue.h"
#include "hybridtest/io/run_reader.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/runner/plan.h"
#include "hybridtest/runner/open_run.h"
#include "hybridtest/runner/session.h"
#include "support/temp_dir.h"

namespace hybridtest::runner {
namespace {

namespace fs = std::filesystem;
const std::string kExample = std::string(HYBRIDTEST_SOURCE_DIR) + "/examples/06_blade_two_actuators/";

io::RunData RunToFile(io::RunSpec spec, const std::string& name) {
  // One folder per test process: ctest runs the tests of this file in parallel.
  static const fs::path dir = test_support::FreshTempDir("multi_actuator_mros");
  const fs::path csv = dir / (name + ".csv");
  for (const auto& f : {csv, fs::path(csv).replace_extension(".meta.json"),
                        fs::path(csv).replace_extension(".state.json"),
                        dir / (name + ".stages.csv"), dir / (name + ".stages.meta.json")}) {
    fs::remove(f);
  }
  spec.output.csv_path = csv.string();
  spec.quiet = true;
  OpenedRun opened = OpenRun(spec);
  Session session(std::move(spec), std::move(opened));
  const StepResult r = session.Run();
  EXPECT_EQ(r.status, SessionStatus::kFinished) << r.reason;
  return io::LoadRun(csv.string());
}

io::RunData Reference() {
  io::RunSpec spec = io::LoadRunSpec(kExample + "dummy.yaml");
  spec.scheme.tableau = integrators::FindTableau("rk4");
  spec.scheme.dt = 1e-4;
  spec.scheme.steps = 100000;
  return RunToFile(std::move(spec), "reference");
}

TEST(MultiActuatorMrOs, MeasuredCoupledK0MeetsOnePercent) {
  const io::RunData reference = Reference();
  io::RunSpec spec = io::LoadRunSpec(kExample + "mr-os.yaml");
  const multibody::Model model = spec.model.model;
  const io::RunData run = RunToFile(std::move(spec), "mr-os");
  double p2p = 0.0;
  const double error = RelativeError(model, run, reference, 0, &p2p);
  EXPECT_GT(p2p, 1e-3);
  EXPECT_LT(error, 0.01);
  // Far fewer evaluations than the 20,000 of Heun at 1 ms.
  EXPECT_LT(run.num_rows(), 20000);
}

TEST(MultiActuatorMrOs, K0WithoutItsCouplingIsWorse) {
  const io::RunData reference = Reference();
  io::RunSpec exact = io::LoadRunSpec(kExample + "mr-os.yaml");
  io::RunSpec uncoupled = io::LoadRunSpec(kExample + "mr-os.yaml");
  auto& physical = *uncoupled.substructures.at(0).physical;
  physical.stiffness_ramp.reset();
  Eigen::Matrix2d diag;
  diag << 7520.0, 0.0, 0.0, 1920.0;  // the diagonal of Tᵀ K T only
  physical.initial_stiffness_matrix = diag;
  const multibody::Model model = exact.model.model;
  const double e_exact = RelativeError(model, RunToFile(std::move(exact), "exact"), reference, 0);
  const double e_uncoupled =
      RelativeError(model, RunToFile(std::move(uncoupled), "uncoupled"), reference, 0);
  EXPECT_GT(e_uncoupled, 10.0 * e_exact);
}

}  // namespace
}  // namespace hybridtest::runner
