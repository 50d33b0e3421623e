// hybridtest._core.time_transfer: the cost of one evaluation of a Python transfer system
// against a C++ in-process one (NumericalLoopback with a linear spring), both called through
// transfer::TransferSystem::Execute from C++ without the GIL held, as the run loop calls them,
// in the same process and the same call. Used by bench/python_transfer.py; not a test.
#include <fmt/core.h>

#include <chrono>

#include "bindings.h"
#include "hybridtest/constitutive/linear_spring.h"
#include "hybridtest/transfer/numerical_loopback.h"
#include "py_objects.h"

namespace hybridtest::python {
namespace {

// Mean wall time of one Execute [s] over `n` commands sweeping ±1 mm about p0.
double TimeExecute(transfer::TransferSystem& ts, long n, double p0) {
  ts.Activate();
  double sink = 0.0;
  const auto start = std::chrono::steady_clock::now();
  for (long i = 0; i < n; ++i) {
    sink += ExecuteOne(ts, p0 + 1e-3 * static_cast<double>(i % 200 - 100) / 100.0).force;
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ts.Deactivate();
  if (sink == 1e300) fmt::print("{}", sink);  // keeps the loop
  return seconds / static_cast<double>(n);
}

}  // namespace

void BindTiming(py::module_& m) {
  m.def(
      "time_transfer",
      [](py::object driver, long n, double stiffness, double p0) {
        PyTransfer python(std::make_shared<SharedObject>(driver), "timing", {transfer::SafetyLimits{}});
        transfer::NumericalLoopback cpp(
            std::make_unique<constitutive::LinearSpring>(stiffness), p0);
        double t_python = 0.0, t_cpp = 0.0;
        {
          py::gil_scoped_release release;
          t_cpp = TimeExecute(cpp, n, p0);
          t_python = TimeExecute(python, n, p0);
        }
        py::dict out;
        out["evaluations"] = n;
        out["python_seconds"] = t_python;
        out["cpp_seconds"] = t_cpp;
        out["ratio"] = t_python / t_cpp;
        return out;
      },
      py::arg("driver"), py::arg("n") = 100000, py::arg("stiffness") = 7200.0,
      py::arg("p0") = 0.02,
      "Mean seconds per Execute of `driver` (a Python transfer system) and of the C++ "
      "NumericalLoopback (linear spring), measured in this call, and their ratio");
}

}  // namespace hybridtest::python
