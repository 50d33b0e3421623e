// Cost of the engine's right-hand side on models read from model files (docs/model-files.md).
//
//   ModelFile/RotorFileOverCpp   ẋ = f_rhs(t, x, r) of examples/models/rotor.yaml against the
//                                built-in C++ rotor (3 blades), measured in one loop: blocks of
//                                kBlock file-model calls and kBlock C++-model calls alternate,
//                                each timed with steady_clock; counters file_ns, cpp_ns (per
//                                call) and ratio (target ≤ 1.3).
//   ModelFile/ChainRhs/n         f_rhs of a planar n-link chain read from a model file
//                                (tests/support/chain_model_file.h), n = 4, 10, 30, 100
//   ModelFile/ChainScaling       the four chain sizes timed in alternating blocks in one run;
//                                counters ns_<n> and `exponent`, the least-squares slope of
//                                log(time) against log(n)
//
// Every benchmark cycles through kStates random states and passes the result through
// benchmark::DoNotOptimize.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <random>
#include <vector>

#include "hybridtest/modelfile/model_file.h"
#include "hybridtest/multibody/kane.h"
#include "support/chain_model_file.h"

namespace hybridtest::bench {
namespace {

constexpr int kStates = 16;  // power of two: the index is a mask
using Clock = std::chrono::steady_clock;

struct Input {
  double t;
  Eigen::VectorXd x;  // (2n)
  Eigen::VectorXd r;  // (num_slots)
};

std::vector<Input> Inputs(const multibody::Model& model, double q_scale) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Input> in(kStates);
  for (Input& s : in) {
    s.t = 2.0 * std::abs(unit(rng));
    s.x.resize(model.num_states());
    for (int i = 0; i < model.num_states(); ++i) s.x(i) = (i < model.num_coordinates() ? q_scale : 1.0) * unit(rng);
    s.r.resize(model.num_slots());
    for (int i = 0; i < model.num_slots(); ++i) s.r(i) = 50.0 * unit(rng);
  }
  return in;
}

models::BuiltModel FromText(const std::string& text) {
  const modelfile::ModelFile f = modelfile::ParseModelFile(YamlInput::FromText(text, "chain.yaml"));
  return modelfile::BuildModelFile(f, f.parameters);
}

// Seconds for `calls` right-hand sides of `model`.
double TimeBlock(const multibody::Model& model, multibody::Data<double>& data,
                 const std::vector<Input>& in, Eigen::VectorXd& xdot, int calls) {
  const auto t0 = Clock::now();
  for (int k = 0; k < calls; ++k) {
    const Input& s = in[k & (kStates - 1)];
    multibody::CalcStateDerivative<double>(model, data, s.t, s.x, s.r, xdot);
    benchmark::DoNotOptimize(xdot.data());
    benchmark::ClobberMemory();
  }
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

void BM_RotorFileOverCpp(benchmark::State& state) {
  constexpr int kBlock = 256;
  const modelfile::ModelFile f = modelfile::LoadModelFile(HYBRIDTEST_SOURCE_DIR "/examples/models/rotor.yaml");
  const models::BuiltModel file = modelfile::BuildModelFile(f, f.parameters);
  const models::BuiltModel cpp = models::BuildModel("rotor", 3, models::DefaultParameters("rotor", 3));
  multibody::Data<double> data_file(file.model), data_cpp(cpp.model);
  const std::vector<Input> in = Inputs(cpp.model, 0.05);
  Eigen::VectorXd xdot(8);
  double file_s = 0.0, cpp_s = 0.0;
  long calls = 0;
  for (auto _ : state) {
    file_s += TimeBlock(file.model, data_file, in, xdot, kBlock);
    cpp_s += TimeBlock(cpp.model, data_cpp, in, xdot, kBlock);
    calls += kBlock;
  }
  state.counters["file_ns"] = 1e9 * file_s / static_cast<double>(calls);
  state.counters["cpp_ns"] = 1e9 * cpp_s / static_cast<double>(calls);
  state.counters["ratio"] = file_s / cpp_s;
}
BENCHMARK(BM_RotorFileOverCpp)->Name("ModelFile/RotorFileOverCpp");

void BM_ChainRhs(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const models::BuiltModel chain = FromText(test_support::ChainModelFile(n, std::min(n, 8)));
  multibody::Data<double> data(chain.model);
  const std::vector<Input> in = Inputs(chain.model, 0.3);
  Eigen::VectorXd xdot(2 * n);
  int k = 0;
  for (auto _ : state) {
    const Input& s = in[(k++) & (kStates - 1)];
    multibody::CalcStateDerivative<double>(chain.model, data, s.t, s.x, s.r, xdot);
    benchmark::DoNotOptimize(xdot.data());
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_ChainRhs)->Name("ModelFile/ChainRhs")->Arg(4)->Arg(10)->Arg(30)->Arg(100);

void BM_ChainScaling(benchmark::State& state) {
  const std::vector<int> sizes = {4, 10, 30, 100};
  std::vector<models::BuiltModel> chains;
  std::vector<multibody::Data<double>> data;
  std::vector<std::vector<Input>> in;
  std::vector<Eigen::VectorXd> xdot;
  for (int n : sizes) {
    chains.push_back(FromText(test_support::ChainModelFile(n, std::min(n, 8))));
  }
  for (const auto& c : chains) {
    data.emplace_back(c.model);
    in.push_back(Inputs(c.model, 0.3));
    xdot.emplace_back(c.model.num_states());
  }
  std::vector<double> seconds(sizes.size(), 0.0);
  std::vector<long> calls(sizes.size(), 0);
  for (auto _ : state) {
    for (std::size_t i = 0; i < sizes.size(); ++i) {
      const int block = std::max(4, 20000 / (sizes[i] * sizes[i]));
      seconds[i] += TimeBlock(chains[i].model, data[i], in[i], xdot[i], block);
      calls[i] += block;
    }
  }
  // Least-squares slope of log(time per call) against log(n).
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    const double per_call = seconds[i] / static_cast<double>(calls[i]);
    state.counters["ns_" + std::to_string(sizes[i])] = 1e9 * per_call;
    const double x = std::log(sizes[i]), y = std::log(per_call);
    sx += x; sy += y; sxx += x * x; sxy += x * y;
  }
  const double m = static_cast<double>(sizes.size());
  state.counters["exponent"] = (m * sxy - sx * sy) / (m * sxx - sx * sx);
}
BENCHMARK(BM_ChainScaling)->Name("ModelFile/ChainScaling");

}  // namespace
}  // namespace hybridtest::bench
