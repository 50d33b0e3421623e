// Cost of one right-hand-side evaluation ẋ = f_rhs(t, x, r) of the paper's rotor (3 blades,
// Table 1): the generic Kane engine against a hand-written closed form (rotor_closed_form.h).
//
//   RotorRhs/KaneEngine            CalcStateDerivative<double>, model from BuildModel("rotor"),
//                                  preallocated Data<double>
//   RotorRhs/ClosedForm            CalcRotorRhs: M and g written out, fixed-size 4×4 Cholesky
//   RotorRhs/ClosedFormArrow       the same with the arrow-structure solve (information)
//   RotorRhs/KaneEngineAutoDiff    CalcStateDerivative<AutoDiff> with 8 seeded directions, the
//                                  cost of one exact Jacobian ∂ẋ/∂x (information)
//   RotorRhs/EngineOverClosedForm  the ratio, measured in one loop: blocks of kBlock engine
//                                  calls and kBlock closed-form calls alternate, each block
//                                  timed with steady_clock; counters engine_ns, closed_form_ns
//                                  (per call) and ratio. Alternating blocks make the ratio
//                                  robust to the load of a shared machine.
//   RotorRhs/SympyC                C generated at build time by bench/sympy/rotor_sympy_codegen.py
//                                  (SymPy's KanesMethod, cse, a dense 4×4 Cholesky); built only
//                                  when python3 with sympy is found (bench/CMakeLists.txt).
//                                  Its q̈ is checked against the engine's on every state first.
//   RotorRhs/EngineOverSympyC      the engine ÷ the generated C, alternating blocks as above.
//   RotorRhs/Compiled              CalcStateDerivative<double> with the rotor's compiled
//                                  right-hand side attached (`compiled: true`; the C of
//                                  `hybridtest equations --format c`, built with the system C
//                                  compiler into the cache of compiled models on first use)
//   RotorRhs/CompiledOverClosedForm, CompiledOverEngine, CompiledOverSympyC
//                                  the compiled model ÷ the closed form, ÷ the numeric engine
//                                  and ÷ SymPy's C, alternating blocks as above (counters
//                                  engine_ns: the compiled model's time per call).
//
// Every benchmark cycles through the same kStates random states (t, x, r), so nothing is
// constant-folded, and passes the result through benchmark::DoNotOptimize.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "hybridtest/models/catalogue.h"
#include "hybridtest/multibody/kane.h"
#include "hybridtest/symbolic/compiled_model.h"
#include "rotor_closed_form.h"

#ifdef HYBRIDTEST_SYMPY_C
extern "C" void hybridtest_rotor_sympy_rhs(const double* par, double t, const double* x,
                                           const double* r, double* xdot);
#endif

namespace hybridtest::bench {
namespace {

constexpr int kStates = 64;  // power of two: the index is a mask

struct RhsInput {
  double t;
  Eigen::VectorXd x;  // (8)
  Eigen::VectorXd r;  // (3) [N]
  RotorState x_fixed;
  Eigen::Vector3d r_fixed;
};

// States of a running rotor: small deflections, any hub angle, moderate speeds, t through
// the ramp; r = k_b q (the numerical substructure).
const std::vector<RhsInput>& Inputs() {
  static const std::vector<RhsInput> inputs = [] {
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    std::vector<RhsInput> v;
    for (int k = 0; k < kStates; ++k) {
      RhsInput in;
      in.t = 1.0 + unit(rng);
      in.x_fixed << 0.01 * unit(rng), 0.01 * unit(rng), 0.01 * unit(rng), 10.0 * unit(rng),
          0.5 * unit(rng), 0.5 * unit(rng), 0.5 * unit(rng), 20.0 * unit(rng);
      in.r_fixed = 7.2e3 * in.x_fixed.head<3>();
      in.x = in.x_fixed;
      in.r = in.r_fixed;
      v.push_back(in);
    }
    return v;
  }();
  return inputs;
}

const multibody::Model& RotorModel() {
  static const models::BuiltModel built =
      models::BuildModel("rotor", 3, models::DefaultParameters("rotor", 3));
  return built.model;
}

// The rotor with its compiled right-hand side attached (symbolic/compiled_model.h).
const multibody::Model& CompiledRotorModel() {
  static const multibody::Model model = [] {
    multibody::Model m = RotorModel();
    m.AttachCompiledRhs(symbolic::CompileModel(m, "rotor"));
    return m;
  }();
  return model;
}

void TimeEngine(benchmark::State& state, const multibody::Model& model) {
  multibody::Data<double> data(model);
  Eigen::VectorXd xdot(8);
  const auto& in = Inputs();
  unsigned k = 0;
  for (auto _ : state) {
    const RhsInput& s = in[k++ & (kStates - 1)];
    multibody::CalcStateDerivative<double>(model, data, s.t, s.x, s.r, xdot);
    benchmark::DoNotOptimize(xdot.data());
    benchmark::ClobberMemory();
  }
}
void BM_KaneEngine(benchmark::State& state) { TimeEngine(state, RotorModel()); }
BENCHMARK(BM_KaneEngine)->Name("RotorRhs/KaneEngine");
void BM_Compiled(benchmark::State& state) { TimeEngine(state, CompiledRotorModel()); }
BENCHMARK(BM_Compiled)->Name("RotorRhs/Compiled");

void BM_ClosedForm(benchmark::State& state) {
  const RotorParameters p;
  RotorState xdot;
  const auto& in = Inputs();
  unsigned k = 0;
  for (auto _ : state) {
    const RhsInput& s = in[k++ & (kStates - 1)];
    CalcRotorRhs(p, s.t, s.x_fixed, s.r_fixed, xdot);
    benchmark::DoNotOptimize(xdot.data());
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_ClosedForm)->Name("RotorRhs/ClosedForm");

void BM_ClosedFormArrow(benchmark::State& state) {
  const RotorParameters p;
  RotorState xdot;
  const auto& in = Inputs();
  unsigned k = 0;
  for (auto _ : state) {
    const RhsInput& s = in[k++ & (kStates - 1)];
    CalcRotorRhsArrow(p, s.t, s.x_fixed, s.r_fixed, xdot);
    benchmark::DoNotOptimize(xdot.data());
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_ClosedFormArrow)->Name("RotorRhs/ClosedFormArrow");

void BM_KaneEngineAutoDiff(benchmark::State& state) {
  using multibody::AutoDiff;
  using multibody::Derivatives;
  const multibody::Model& model = RotorModel();
  multibody::Data<AutoDiff> data(model);
  // Seeded inputs, prepared outside the loop: 8 directions (the state).
  std::vector<multibody::VectorX<AutoDiff>> xs, rs;
  for (const RhsInput& s : Inputs()) {
    multibody::VectorX<AutoDiff> x(8);
    for (int i = 0; i < 8; ++i) x(i) = AutoDiff(s.x(i), Derivatives::Unit(8, i));
    xs.push_back(x);
    rs.push_back(s.r.cast<AutoDiff>());
  }
  multibody::VectorX<AutoDiff> xdot(8);
  const auto& in = Inputs();
  unsigned k = 0;
  for (auto _ : state) {
    const unsigned i = k++ & (kStates - 1);
    multibody::CalcStateDerivative<AutoDiff>(model, data, AutoDiff(in[i].t), xs[i], rs[i], xdot);
    benchmark::DoNotOptimize(xdot.data());
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_KaneEngineAutoDiff)->Name("RotorRhs/KaneEngineAutoDiff");

// The engine (on `model`: RotorModel() or CompiledRotorModel()) and a reference timed in
// alternating blocks of 256 calls on the same states, so that both see the same machine load;
// counters engine_ns, <reference>_ns and their ratio. `reference(s)` evaluates the
// reference's ẋ at s.
template <class Reference>
void EngineAgainst(benchmark::State& state, const char* reference_name, Reference&& reference,
                   const multibody::Model& model = RotorModel()) {
  constexpr int kBlock = 256;
  using Clock = std::chrono::steady_clock;
  multibody::Data<double> data(model);
  Eigen::VectorXd xdot(8);
  const auto& in = Inputs();
  double engine_s = 0.0, reference_s = 0.0;
  long calls = 0;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    for (int k = 0; k < kBlock; ++k) {
      const RhsInput& s = in[k & (kStates - 1)];
      multibody::CalcStateDerivative<double>(model, data, s.t, s.x, s.r, xdot);
      benchmark::DoNotOptimize(xdot.data());
      benchmark::ClobberMemory();
    }
    const auto t1 = Clock::now();
    for (int k = 0; k < kBlock; ++k) {
      reference(in[k & (kStates - 1)]);
      benchmark::ClobberMemory();
    }
    const auto t2 = Clock::now();
    engine_s += std::chrono::duration<double>(t1 - t0).count();
    reference_s += std::chrono::duration<double>(t2 - t1).count();
    calls += kBlock;
  }
  if (calls > 0) {
    state.counters["engine_ns"] = 1e9 * engine_s / static_cast<double>(calls);
    state.counters[std::string(reference_name) + "_ns"] =
        1e9 * reference_s / static_cast<double>(calls);
    state.counters["ratio"] = engine_s / reference_s;
  }
}

void BM_EngineOverClosedForm(benchmark::State& state) {
  const RotorParameters p;
  RotorState xdot;
  EngineAgainst(state, "closed_form", [&](const RhsInput& s) {
    CalcRotorRhs(p, s.t, s.x_fixed, s.r_fixed, xdot);
    benchmark::DoNotOptimize(xdot.data());
  });
}
BENCHMARK(BM_EngineOverClosedForm)->Name("RotorRhs/EngineOverClosedForm");

void BM_CompiledOverClosedForm(benchmark::State& state) {
  const RotorParameters p;
  RotorState xdot;
  EngineAgainst(state, "closed_form", [&](const RhsInput& s) {
    CalcRotorRhs(p, s.t, s.x_fixed, s.r_fixed, xdot);
    benchmark::DoNotOptimize(xdot.data());
  }, CompiledRotorModel());
}
BENCHMARK(BM_CompiledOverClosedForm)->Name("RotorRhs/CompiledOverClosedForm");

void BM_CompiledOverEngine(benchmark::State& state) {
  multibody::Data<double> data(RotorModel());
  Eigen::VectorXd xdot(8);
  EngineAgainst(state, "numeric_engine", [&](const RhsInput& s) {
    multibody::CalcStateDerivative<double>(RotorModel(), data, s.t, s.x, s.r, xdot);
    benchmark::DoNotOptimize(xdot.data());
  }, CompiledRotorModel());
}
BENCHMARK(BM_CompiledOverEngine)->Name("RotorRhs/CompiledOverEngine");

#ifdef HYBRIDTEST_SYMPY_C
// The generated function's parameter vector (its order is the script's).
std::array<double, 8> SympyParameters() {
  const RotorParameters p;
  return {p.l_b, p.m_b, p.zeta_b, p.f_w, p.I_g, p.d_g, p.g, p.t0};
}

// Worst relative difference of ẋ between the generated C and the engine over every state;
// the benchmarks refuse to time code that disagrees.
bool SympyAgrees(benchmark::State& state) {
  const multibody::Model& model = RotorModel();
  multibody::Data<double> data(model);
  Eigen::VectorXd xdot(8);
  const auto par = SympyParameters();
  double worst = 0.0;
  for (const RhsInput& s : Inputs()) {
    multibody::CalcStateDerivative<double>(model, data, s.t, s.x, s.r, xdot);
    double y[8];
    hybridtest_rotor_sympy_rhs(par.data(), s.t, s.x.data(), s.r.data(), y);
    for (int i = 0; i < 8; ++i) {
      worst = std::max(worst, std::abs(y[i] - xdot(i)) / std::max(1.0, std::abs(xdot(i))));
    }
  }
  state.counters["max_rel_diff"] = worst;
  if (!(worst <= 1e-10)) {
    state.SkipWithError("the SymPy-generated C disagrees with the engine on x'");
    return false;
  }
  return true;
}

void BM_SympyC(benchmark::State& state) {
  if (!SympyAgrees(state)) return;
  const auto par = SympyParameters();
  double xdot[8];
  const auto& in = Inputs();
  unsigned k = 0;
  for (auto _ : state) {
    const RhsInput& s = in[k++ & (kStates - 1)];
    hybridtest_rotor_sympy_rhs(par.data(), s.t, s.x.data(), s.r.data(), xdot);
    benchmark::DoNotOptimize(xdot);
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_SympyC)->Name("RotorRhs/SympyC");

void BM_EngineOverSympyC(benchmark::State& state) {
  if (!SympyAgrees(state)) return;
  const auto par = SympyParameters();
  double y[8];
  EngineAgainst(state, "sympy_c", [&](const RhsInput& s) {
    hybridtest_rotor_sympy_rhs(par.data(), s.t, s.x.data(), s.r.data(), y);
    benchmark::DoNotOptimize(y);
  });
}
BENCHMARK(BM_EngineOverSympyC)->Name("RotorRhs/EngineOverSympyC");

void BM_CompiledOverSympyC(benchmark::State& state) {
  if (!SympyAgrees(state)) return;
  const auto par = SympyParameters();
  double y[8];
  EngineAgainst(state, "sympy_c", [&](const RhsInput& s) {
    hybridtest_rotor_sympy_rhs(par.data(), s.t, s.x.data(), s.r.data(), y);
    benchmark::DoNotOptimize(y);
  }, CompiledRotorModel());
}
BENCHMARK(BM_CompiledOverSympyC)->Name("RotorRhs/CompiledOverSympyC");
#endif  // HYBRIDTEST_SYMPY_C

}  // namespace
}  // namespace hybridtest::bench
