// hybridtest._core.modes: `hybridtest modes` from Python, through the same implementation
// (io::AnalyseModes: the file or config, the overrides, the operating point, the steady state,
// the linearisation). Returns a dict that python/hybridtest/__init__.py wraps as ModeAnalysis:
//
//   {model, time, start, x, states, A, equilibrium, residual, modes: [{label, dominant,
//    unstable, eigenvalue, frequency_hz, damped_frequency_hz, damping_ratio, shape}], steady: None | {coordinates, values, iterations, residual,
//    residual_speed, residual_unit, converged, driven}}
//
// Arrays are numpy (A float64, shape complex128); everything is SI.
#include <pybind11/complex.h>
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <fmt/core.h>

#include <optional>

#include "bindings.h"
#include "hybridtest/common/error.h"
#include "hybridtest/io/modes_analysis.h"

namespace hybridtest::python {
namespace {

// at = {"q": [...], "u": [...]} (either may be left out).
void ReadAt(const std::optional<py::dict>& at, io::ModesRequest& request) {
  if (!at) return;
  for (const auto& [key, value] : *at) {
    const std::string name = py::str(key);
    if (name != "q" && name != "u") {
      throw ConfigError(fmt::format("modes(at=...): unknown key '{}'; give {{\"q\": [...], "
                                    "\"u\": [...]}} (either may be left out), SI", name));
    }
    (name == "q" ? request.q : request.u) = value.cast<std::vector<double>>();
  }
}

py::dict Modes(const std::string& path, const std::optional<py::dict>& at,
               const std::optional<py::dict>& set, double time,
               const std::vector<std::string>& steady, const std::vector<std::string>& driven,
               double tolerance, int max_iterations) {
  io::ModesRequest request;
  request.path = path;
  request.time = time;
  request.steady = steady;
  request.driven = driven;
  if (!(tolerance > 0.0)) {
    throw ConfigError(fmt::format("modes(tolerance={}): expected a positive tolerance on |u̇| "
                                  "in the speed rates' units", tolerance));
  }
  if (max_iterations < 1 || max_iterations > multibody::kMaxSteadyIterations) {
    throw ConfigError(fmt::format("modes(max_iterations={}): expected 1 to {}, as "
                                  "`hybridtest modes --steady-iterations`", max_iterations,
                                  multibody::kMaxSteadyIterations));
  }
  request.steady_options.tolerance = tolerance;
  request.steady_options.max_iterations = max_iterations;
  if (set) {
    for (const auto& [key, value] : *set) {
      request.set.emplace_back(py::str(key).cast<std::string>(), value.cast<double>());
    }
  }
  ReadAt(at, request);
  const io::ModesReport report = io::AnalyseModes(request);
  const multibody::Model& model = report.built.model;
  const multibody::ModeAnalysis& a = report.analysis;
  py::dict out;
  out["model"] = report.built.name;
  out["time"] = time;
  out["start"] = report.start;
  out["x"] = a.x;
  out["states"] = a.linearization.state_names;
  out["A"] = a.linearization.A;
  py::list modes;
  for (std::size_t k = 0; k < a.modes.size(); ++k) {
    const multibody::Mode& m = a.modes[k];
    py::dict d;
    d["label"] = report.readouts[k].label;
    d["dominant"] = report.readouts[k].dominant;
    d["unstable"] = report.readouts[k].unstable;
    d["eigenvalue"] = m.eigenvalue;
    d["frequency_hz"] = m.frequency_hz;
    d["damped_frequency_hz"] = m.damped_frequency_hz;
    d["damping_ratio"] = m.damping_ratio;
    d["shape"] = m.shape;
    modes.append(d);
  }
  out["modes"] = modes;
  out["equilibrium"] = report.equilibrium;
  out["residual"] = report.residual.residual;  // max |u̇| at x (0 with steady=)
  out["steady"] = py::none();
  if (report.steady) {
    const multibody::SteadyState& s = *report.steady;
    py::dict d;
    py::list names, values;
    for (int k : s.free_coordinates) {
      names.append(model.coordinates()[static_cast<std::size_t>(k)].name);
      values.append(s.x(k));
    }
    d["coordinates"] = names;
    d["values"] = values;
    d["iterations"] = s.iterations;
    d["residual"] = s.residual;
    d["residual_speed"] = model.speeds()[static_cast<std::size_t>(s.worst_speed)].name;
    d["residual_unit"] = multibody::SpeedRateUnit(model, s.worst_speed);
    d["converged"] = s.converged;
    py::list drives;
    for (int k : s.driven_speeds) drives.append(model.speeds()[static_cast<std::size_t>(k)].name);
    d["driven"] = drives;
    out["steady"] = d;
  }
  return out;
}

}  // namespace

void BindModes(py::module_& m) {
  m.def("modes", &Modes, py::arg("path"), py::arg("at") = py::none(),
        py::arg("set") = py::none(), py::arg("time") = 0.0,
        py::arg("steady") = std::vector<std::string>{},
        py::arg("driven") = std::vector<std::string>{}, py::arg("tolerance") = 1e-10,
        py::arg("max_iterations") = 50,
        "`hybridtest modes` as a dict (hybridtest.modes wraps it as a ModeAnalysis).");
}

}  // namespace hybridtest::python
