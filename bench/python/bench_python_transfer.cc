// The cost of one Python-transfer evaluation against a C++ in-process one, with the Python
// interpreter embedded: the same spring, r = k (command − p0), behind transfer::TransferSystem
// once as a Python bench driver (python/src/py_objects.h: PyTransfer, the class the package
// puts behind a physical slot) and once as the C++ NumericalLoopback. Both are called from C++
// without the GIL held, as the run loop calls them; each benchmark iteration times a batch of
// each, back to back, so the ratio is measured in the same run on the same load. Batches are
// timed in the thread's CPU time (CLOCK_THREAD_CPUTIME_ID): on a shared, loaded machine the
// wall time of a 30 µs batch is mostly other processes' turns.
//
//   build/release/bench/hybridtest_bench_python
//
// Counters: python_ns and cpp_ns per Execute, ratio = python_ns / cpp_ns.
#include <benchmark/benchmark.h>
#include <pybind11/embed.h>

#include <time.h>

#include <memory>

#include "hybridtest/constitutive/linear_spring.h"
#include "hybridtest/transfer/numerical_loopback.h"
#include "py_objects.h"

namespace py = pybind11;
using hybridtest::python::PyTransfer;
using hybridtest::python::SharedObject;

namespace {

constexpr double kStiffness = 7200.0;  // [N/m]
constexpr double kP0 = 0.02;           // [m]
constexpr int kBatch = 2000;           // Executes per timed batch

double ThreadCpuNs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e9 + static_cast<double>(ts.tv_nsec);
}

// Mean nanoseconds (thread CPU time) per Execute over one batch sweeping ±1 mm about p0.
double TimeBatch(hybridtest::transfer::TransferSystem& ts) {
  double sink = 0.0;
  const double start = ThreadCpuNs();
  for (int i = 0; i < kBatch; ++i) {
    sink += ExecuteOne(ts, kP0 + 1e-3 * static_cast<double>(i % 200 - 100) / 100.0).force;
  }
  benchmark::DoNotOptimize(sink);
  return (ThreadCpuNs() - start) / kBatch;
}

void BM_PythonTransferExecute(benchmark::State& state) {
  std::unique_ptr<PyTransfer> python;
  {
    py::gil_scoped_acquire gil;
    py::dict scope;
    py::exec(R"(
class Spring:
    def __init__(self, k, p0): self.k, self.p0 = k, p0
    def activate(self): pass
    def execute(self, command): return command, self.k * (command - self.p0)
    def hold(self): pass
    def deactivate(self): pass
)", scope);
    python = std::make_unique<PyTransfer>(
        std::make_shared<SharedObject>(scope["Spring"](kStiffness, kP0)), "r1",
        std::vector<hybridtest::transfer::SafetyLimits>{hybridtest::transfer::SafetyLimits{}});
  }
  hybridtest::transfer::NumericalLoopback cpp(
      std::make_unique<hybridtest::constitutive::LinearSpring>(kStiffness), kP0);
  python->Activate();
  cpp.Activate();
  double python_ns = 0.0, cpp_ns = 0.0;
  for (auto _ : state) {
    cpp_ns += TimeBatch(cpp);
    python_ns += TimeBatch(*python);
  }
  python->Deactivate();
  cpp.Deactivate();
  const auto n = static_cast<double>(state.iterations());
  state.counters["python_ns"] = python_ns / n;
  state.counters["cpp_ns"] = cpp_ns / n;
  state.counters["ratio"] = python_ns / cpp_ns;
  state.SetItemsProcessed(state.iterations() * 2 * kBatch);
  py::gil_scoped_acquire gil;
  python.reset();
}
BENCHMARK(BM_PythonTransferExecute)->Unit(benchmark::kMillisecond)->Repetitions(5);

}  // namespace

int main(int argc, char** argv) {
  py::scoped_interpreter interpreter;
  py::gil_scoped_release release;  // as in a run: the GIL is taken by each Python call
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
