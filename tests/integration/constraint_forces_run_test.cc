// The journal's constraint-force channels through the real binary: the slider-crank
// (examples/models/slider_crank.yaml, `record_force: true` on its rod pin) with its spring on an
// emulated ideal bench. The channels carry the force of the rod on the pin in N, equal to the
// engine's multipliers at each row's state; a run killed (SIGKILL) and resumed ends with the
// uninterrupted journal, these channels included.
#include "hybridtest/io/run_reader.h"
#include "hybridtest/modelfile/model_file.h"
#include "hybridtest/multibody/constraints.h"
#include "hybridtest/multibody/kane.h"
#include "integration/resume_support.h"

namespace hybridtest::testing {
namespace {

const char* kBench = R"(bench:
  units: {length: mm, force: N}
  seed: 1
  pacing: accelerated
  p0_mm: 0
  specimen: {type: linear, stiffness: 2000}
  actuator:
    position_min_mm: -150
    position_max_mm: 150
    capacity_kN: 10
    velocity_limit_mm_per_s: 5000
    lag: {type: none}
    delay_ms: 0
  load_cell: {noise_std_N: 0, resolution_N: 0, offset_N: 0}
  settling: {tolerance_mm: 0.001, dwell_ms: 0}
  sampling: {window_ms: 1}
  timing: {overhead_ms: 0, internal_step_ms: 1}
  safety:
    stroke_min_mm: -150
    stroke_max_mm: 150
    max_increment_mm: 5
    force_soft_kN: 0.5
    force_hard_kN: 0.6
    timeout_s: 5
)";

std::string Config(const fs::path& dir) {
  std::ofstream(dir / "bench.yaml") << kBench;
  const fs::path config = dir / "slider_crank_emulated.yaml";
  std::ofstream(config) << fmt::format(R"(model:
  file: {}/examples/models/slider_crank.yaml
integrator:
  tableau: rk4
  dt: 0.001
duration: 1.0
substructures:
  r1:
    type: physical
    transfer: {{type: emulated, config: bench.yaml}}
    setup: {{p0: 0.0, sign: 1, scale: 1}}
    safety: {{stroke_min: -0.15, stroke_max: 0.15, max_increment: 0.005, force_soft: 500,
              force_hard: 600, timeout: 5}}
)", kSource);
  return config.string();
}

TEST(ConstraintForcesRun, TheRodForceIsJournalledInNewtonsAndSurvivesAKill) {
  const fs::path dir = ResumeTestDir("constraint_forces");
  const std::string config = Config(dir);
  const fs::path reference = dir / "reference.csv";
  ASSERT_EQ(RunToEnd(RunArgs(config, reference), dir / "reference.log"), 0);

  // The channels: named after the constraint, in N, and the engine's multipliers at each
  // row's state (q, u and the measured r1 of the row).
  const io::RunData run = io::LoadRun(reference.string());
  const nlohmann::json sidecar = Sidecar(reference);
  int found = 0;
  for (const auto& c : sidecar["channels"]) {
    const std::string name = c["name"];
    if (name.starts_with("rod_on_the_slider_pin_reaction_")) {
      EXPECT_EQ(c["unit"], "N") << name;
      ++found;
    }
  }
  EXPECT_EQ(found, 2);
  const modelfile::ModelFile file =
      modelfile::LoadModelFile(kSource + "/examples/models/slider_crank.yaml");
  const models::BuiltModel built = modelfile::BuildModelFile(file, file.parameters);
  const multibody::Model& model = built.model;
  multibody::Data<double> data(model);
  Eigen::VectorXd xdot(model.num_states()), lambda(model.num_constraint_rows());
  const Eigen::VectorXd fx = run.Get("rod_on_the_slider_pin_reaction_x");
  const Eigen::VectorXd fy = run.Get("rod_on_the_slider_pin_reaction_y");
  ASSERT_EQ(run.num_rows(), 1001);
  double largest = 0.0;
  for (long i = 0; i < run.num_rows(); i += 97) {
    Eigen::VectorXd x(6), r(1);
    int k = 0;
    for (const char* q : {"q1", "q2", "q3", "u1", "u2", "u3"}) x(k++) = run.Get(q)(i);
    r(0) = run.Get("r1")(i);
    multibody::CalcStateDerivative<double>(model, data, run.Get("t")(i), x, r, xdot);
    multibody::CalcConstraintForces(model, data, lambda);
    EXPECT_NEAR(fx(i), lambda(0), 1e-9 * (1.0 + std::abs(lambda(0)))) << "row " << i;
    EXPECT_NEAR(fy(i), lambda(1), 1e-9 * (1.0 + std::abs(lambda(1)))) << "row " << i;
    largest = std::max(largest, std::abs(fx(i)));
  }
  EXPECT_GT(largest, 1.0) << "the rod carries a force [N]";

  // Killed halfway and resumed: the same journal (the bench's lab time aside).
  const auto expected = ReadLines(reference);
  const fs::path csv = dir / "killed.csv";
  if (RunAndSignalAt(RunArgs(config, csv), csv, fs::file_size(reference) / 2, SIGKILL,
                     dir / "run.log", 128 + SIGKILL)) {
    const auto [status, output] = Resume(csv, {}, dir / "resume.log");
    ASSERT_EQ(status, 0) << output;
    ExpectSameJournal(expected, ReadLines(csv), true);
    EXPECT_EQ(Sidecar(csv)["status"], "completed");
  } else {
    std::cout << "[ the run ended before the kill: resume not exercised ]\n";
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hybridtest::testing
