// Cost of a constrained right-hand side (docs/decisions/0023-constraints.md):
//
//   Constraints/BicycleOverTree   ẋ of examples/models/whipple_bicycle.yaml (8 speeds, 5
//                                 constraint rows: the reduced equations) against the same
//                                 file without its constraints (the unconstrained tree: the
//                                 same kinematics, M and g, then a Cholesky solve), measured in
//                                 one loop of alternating blocks of kBlock calls, each timed
//                                 with steady_clock; counters constrained_ns, tree_ns (per
//                                 call) and ratio.
//
// Both cycle through kStates consistent states of the bicycle (assembled at random roll,
// steer and speeds).
#include <benchmark/benchmark.h>

#include <chrono>
#include <fstream>
#include <random>
#include <sstream>
#include <vector>

#include "hybridtest/modelfile/model_file.h"
#include "hybridtest/multibody/assembly.h"
#include "hybridtest/multibody/kane.h"

namespace hybridtest::bench {
namespace {

constexpr int kStates = 16;
using Clock = std::chrono::steady_clock;

models::BuiltModel FromText(const std::string& text) {
  const modelfile::ModelFile f = modelfile::ParseModelFile(YamlInput::FromText(text, "bicycle.yaml"));
  return modelfile::BuildModelFile(f, f.parameters);
}

double TimeBlock(const multibody::Model& model, multibody::Data<double>& data,
                 const std::vector<Eigen::VectorXd>& in, Eigen::VectorXd& xdot, int calls) {
  const Eigen::VectorXd r(0);
  const auto t0 = Clock::now();
  for (int k = 0; k < calls; ++k) {
    multibody::CalcStateDerivative<double>(model, data, 0.0, in[k & (kStates - 1)], r, xdot);
    benchmark::DoNotOptimize(xdot.data());
    benchmark::ClobberMemory();
  }
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

void BM_BicycleOverTree(benchmark::State& state) {
  constexpr int kBlock = 256;
  std::ifstream file(HYBRIDTEST_SOURCE_DIR "/examples/models/whipple_bicycle.yaml");
  std::stringstream text;
  text << file.rdbuf();
  const std::string full = text.str();
  const models::BuiltModel bicycle = FromText(full);
  const models::BuiltModel tree = FromText(full.substr(0, full.find("\nconstraints:")));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Eigen::VectorXd> in;
  for (int k = 0; k < kStates; ++k) {
    Eigen::VectorXd x = bicycle.model.initial_state();
    x(3) = 0.2 * unit(rng);                       // roll
    x(6) = 0.2 * unit(rng);                       // steer
    x(8 + 3) = unit(rng);                         // roll rate
    x(8 + 5) = -15.0 + 5.0 * unit(rng);           // rear wheel rate
    x(8 + 6) = unit(rng);                         // steer rate
    in.push_back(multibody::AssembleState(bicycle.model, 0.0, x).x);
  }
  multibody::Data<double> data_c(bicycle.model), data_t(tree.model);
  Eigen::VectorXd xdot(16);
  double c_s = 0.0, t_s = 0.0;
  long calls = 0;
  for (auto _ : state) {
    c_s += TimeBlock(bicycle.model, data_c, in, xdot, kBlock);
    t_s += TimeBlock(tree.model, data_t, in, xdot, kBlock);
    calls += kBlock;
  }
  state.counters["constrained_ns"] = 1e9 * c_s / static_cast<double>(calls);
  state.counters["tree_ns"] = 1e9 * t_s / static_cast<double>(calls);
  state.counters["ratio"] = c_s / t_s;
}
BENCHMARK(BM_BicycleOverTree)->Name("Constraints/BicycleOverTree");

}  // namespace
}  // namespace hybridtest::bench
