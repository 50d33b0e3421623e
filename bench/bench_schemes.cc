// The numerical cost of one step of each hybrid scheme on the paper's rotor, against the
// Kane right-hand side measured in the same run (the reference), and the scheme's cost per
// SPECIMEN EVALUATION — the figure that matters beside a bench's ~1 s per evaluation.
//
// Method. Each scheme runs the paper's rotor (3 blades, numerical springs behind a seam that
// evaluates r = k d, K0 = k) from the zero state; the benchmark times Step() only.
//   Schemes/Step/heun          explicit RK, h = 1 ms: 2 evaluations per step
//   Schemes/Step/alpha-os      α-OS, h = 5 ms: Jacobian, coupling matrix, LU, Newton
//   Schemes/Step/mr-os         MR-OS, H = 20 ms: 2 × 20 RK4 substeps (predictor, corrector)
//   Schemes/Rhs                one CalcStateDerivative<double> (the reference)
// Counters: rhs_per_step = step time / RHS time; us_per_evaluation = step time / evaluations.
#include <benchmark/benchmark.h>

#include <chrono>
#include <limits>

#include "hybridtest/integrators/catalogue.h"
#include "hybridtest/models/catalogue.h"
#include "hybridtest/multibody/kane.h"
#include "hybridtest/schemes/scheme_config.h"

namespace hybridtest::bench {
namespace {

constexpr double kDuration = 1e6;  // [s] never reached

models::BuiltModel Rotor() {
  return models::BuildModel("rotor", 3, models::DefaultParameters("rotor", 3));
}

double RhsNanoseconds(const multibody::Model& model) {
  multibody::Data<double> data(model);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(2 * model.num_coordinates()), xdot(x.size());
  Eigen::VectorXd r = Eigen::VectorXd::Zero(model.num_slots());
  const int n = 20000;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < n; ++i) {
    x(0) = 1e-6 * i;
    multibody::CalcStateDerivative<double>(model, data, 0.0, x, r, xdot);
    benchmark::DoNotOptimize(xdot.data());
  }
  return std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - start).count() / n;
}

void SchemeStep(benchmark::State& state, schemes::SchemeKind kind, double dt) {
  const models::BuiltModel rotor = Rotor();
  const multibody::Model& model = rotor.model;
  const int m = model.num_slots();
  schemes::SchemeConfig config;
  config.kind = kind;
  schemes::SlotInfo slots{Eigen::VectorXd::Constant(m, 7200.0),
                          Eigen::VectorXd::Constant(m, std::numeric_limits<double>::infinity()), {}};
  auto scheme = schemes::MakeScheme(config, integrators::FindTableau("heun"), dt, kDuration,
                                    static_cast<long>(kDuration / dt), model, slots);
  schemes::SeamOf seam([&](const schemes::TrialPoint&, const Eigen::VectorXd& d,
                           Eigen::Ref<Eigen::VectorXd> r) { r = 7200.0 * d; });
  schemes::RowSinkOf rows([](double, const Eigen::VectorXd&, const Eigen::VectorXd&) {});
  Eigen::VectorXd x0 = Eigen::VectorXd::Zero(2 * model.num_coordinates()), r0(m);
  seam.Trial({0, 0, 0.0}, Eigen::VectorXd::Zero(m), r0);
  scheme->Start(0.0, x0, r0);
  long steps = 0;
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state) {
    scheme->Step(seam, rows);
    ++steps;
  }
  const double step_ns =
      std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - start).count() /
      static_cast<double>(std::max(1L, steps));
  const double rhs_ns = RhsNanoseconds(model);
  state.counters["rhs_ns"] = rhs_ns;
  state.counters["rhs_per_step"] = step_ns / rhs_ns;
  state.counters["us_per_evaluation"] = 1e-3 * step_ns / scheme->evaluations_per_step();
}

BENCHMARK_CAPTURE(SchemeStep, heun, schemes::SchemeKind::kRungeKutta, 0.001);
BENCHMARK_CAPTURE(SchemeStep, alpha_os, schemes::SchemeKind::kAlphaOs, 0.005);
BENCHMARK_CAPTURE(SchemeStep, mr_os, schemes::SchemeKind::kMrOs, 0.02);

}  // namespace
}  // namespace hybridtest::bench
