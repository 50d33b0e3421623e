// The cost of an FMU substructure (fmi/fmu_substructure.h) against the built-in law, in the
// same run. One iteration is one step of Heun's method as the session drives a substructure
// (decision 0002): a trial at stage 0 and its commit, then a trial at stage 1.
//   Law          the built-in linear spring (NumericalSubstructure), the reference;
//   FmuStateless the spring FMU of tests/fmi/ (no state: set, get; a fmi2DoStep per commit);
//   FmuStateful  the Maxwell FMU (fmi2SetFMUstate + fmi2DoStep per trial, fmi2GetFMUstate
//                per commit);
//   FmuBoucWen   the Bouc-Wen FMU of examples/fmi/ (stateful as above; its fmi2DoStep takes
//                16 RK4 substeps of the hysteretic displacement).
// Read the ratio of the times per iteration (ns) of each FMU line to the Law line.
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <string>

#include "hybridtest/common/yaml_input.h"
#include "hybridtest/constitutive/linear_spring.h"
#include "hybridtest/fmi/fmu_config.h"
#include "hybridtest/substructures/numerical_substructure.h"

namespace hybridtest::bench {
namespace {

std::unique_ptr<substructures::Substructure> Fmu(const std::string& id, const std::string& params,
                                                 const std::string& dir = HYBRIDTEST_TEST_FMU_DIR) {
  const std::string yaml = "{type: fmu, fmu: " + dir + "/" + id +
                           ".fmu, displacement: x, force: F, parameters: " + params + "}";
  const YamlInput in = YamlInput::FromText(yaml, "bench.yaml");
  return fmi::ParseFmuSubstructure(in, in.root(), "r1", {"r1"}, "substructures.r1", nullptr)
      .Build();
}

void Steps(benchmark::State& state, substructures::Substructure& s) {
  const double h = 0.001;
  long n = 0;
  double d = 0.0;
  double r = 0.0;
  for (auto _ : state) {
    const double t = static_cast<double>(n) * h;
    d = 0.01 * std::sin(t);
    s.Trial(std::span<const double>(&d, 1), std::span<double>(&r, 1), {n, 0, t});
    s.Commit();
    benchmark::DoNotOptimize(r);
    d += 1e-5;
    s.Trial(std::span<const double>(&d, 1), std::span<double>(&r, 1), {n, 1, t + h});
    benchmark::DoNotOptimize(r);
    ++n;
  }
}

void Law(benchmark::State& state) {
  substructures::NumericalSubstructure s(std::make_unique<constitutive::LinearSpring>(7200.0));
  Steps(state, s);
}
void FmuStateless(benchmark::State& state) {
  auto s = Fmu("spring", "{k: 7200}");
  Steps(state, *s);
}
void FmuStateful(benchmark::State& state) {
  auto s = Fmu("maxwell", "{k: 7200, c: 50}");
  Steps(state, *s);
}

void FmuBoucWen(benchmark::State& state) {
  auto s = Fmu("bouc_wen", "{k: 7200, alpha: 0.5, x_y: 0.002, n: 2}", HYBRIDTEST_EXAMPLE_FMU_DIR);
  Steps(state, *s);
}

BENCHMARK(Law);
BENCHMARK(FmuStateless);
BENCHMARK(FmuStateful);
BENCHMARK(FmuBoucWen);

}  // namespace
}  // namespace hybridtest::bench
