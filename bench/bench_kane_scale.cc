// The Kane engine at scale (decision 0012), without MuJoCo (see bench/mujoco/ for the side by
// side): an n-link pendulum and a branched rotor tree from bench/tree_description.h.
//
//   KaneScale/ChainRhs/n        CalcStateDerivative<double>, n = 4, 10, 30, 100
//   KaneScale/RotorTreeRhs      the same on the 3-blade tree (n = 32)
//   KaneScale/MassMatrix/n      the two mass-matrix paths on the chain (whichever Build() picks) in alternating blocks:
//                               counters tree_us, pairwise_us and ratio (tree ÷ pairwise)
#include <benchmark/benchmark.h>

#include <chrono>
#include <random>

#include "hybridtest/multibody/kane.h"
#include "hybridtest/multibody/tree_mass.h"
#include "tree_description.h"

namespace hybridtest::bench {
namespace {

std::vector<Eigen::VectorXd> States(int n) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Eigen::VectorXd> xs;
  for (int s = 0; s < 16; ++s) {
    Eigen::VectorXd x(2 * n);
    for (int i = 0; i < 2 * n; ++i) x(i) = (i < n ? 0.5 : 1.0) * unit(rng);
    xs.push_back(x);
  }
  return xs;
}

void TimeRhs(benchmark::State& state, const multibody::Model& model) {
  const int n = model.num_coordinates();
  multibody::Data<double> data(model);
  const auto xs = States(n);
  const Eigen::VectorXd r = Eigen::VectorXd::Zero(model.num_slots());
  Eigen::VectorXd xdot(2 * n);
  std::size_t s = 0;
  for (auto _ : state) {
    multibody::CalcStateDerivative<double>(model, data, 0.0, xs[s++ & 15], r, xdot);
    benchmark::DoNotOptimize(xdot.data());
  }
  state.SetLabel(model.tree_mass_matrix() ? "tree" : "pairwise");
}

void BM_ChainRhs(benchmark::State& state) {
  TimeRhs(state, BuildKaneModel(ChainDescription(static_cast<int>(state.range(0)))));
}
BENCHMARK(BM_ChainRhs)->Name("KaneScale/ChainRhs")->Arg(4)->Arg(10)->Arg(30)->Arg(100);

void BM_RotorTreeRhs(benchmark::State& state) { TimeRhs(state, BuildKaneModel(RotorTreeDescription(10))); }
BENCHMARK(BM_RotorTreeRhs)->Name("KaneScale/RotorTreeRhs");

void BM_MassMatrix(benchmark::State& state) {
  const multibody::Model model = BuildKaneModel(ChainDescription(static_cast<int>(state.range(0))));
  const int n = model.num_coordinates();
  multibody::Data<double> data(model);
  multibody::CalcKinematics<double>(model, data, 0.0, States(n)[0]);
  const int block = std::max(4, 20000 / (n * n + 8));
  using Clock = std::chrono::steady_clock;
  double tree = 0.0, pairwise = 0.0;
  long calls = 0;
  for (auto _ : state) {
    auto t0 = Clock::now();
    for (int k = 0; k < block; ++k) {
      multibody::internal::CalcTreeMassMatrix<double>(model, data);
      benchmark::DoNotOptimize(data.M.data());
    }
    auto t1 = Clock::now();
    for (int k = 0; k < block; ++k) {
      multibody::CalcMassMatrixPairwise<double>(model, data);
      benchmark::DoNotOptimize(data.M.data());
    }
    auto t2 = Clock::now();
    tree += std::chrono::duration<double>(t1 - t0).count();
    pairwise += std::chrono::duration<double>(t2 - t1).count();
    calls += block;
  }
  state.counters["tree_us"] = 1e6 * tree / static_cast<double>(calls);
  state.counters["pairwise_us"] = 1e6 * pairwise / static_cast<double>(calls);
  state.counters["ratio"] = tree / pairwise;
}
BENCHMARK(BM_MassMatrix)->Name("KaneScale/MassMatrix")->Arg(4)->Arg(10)->Arg(30)->Arg(100);

}  // namespace
}  // namespace hybridtest::bench
