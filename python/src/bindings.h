#pragma once
// The pieces of the Python module hybridtest._core (module.cc puts them together). Every
// quantity crossing into Python is SI, as inside the library; arrays are float64 numpy arrays.
#include <pybind11/pybind11.h>

#include <exception>
#include <string>

namespace hybridtest::python {

namespace py = pybind11;

// The exception classes (Error, ConfigError, ModelError, TransferError, IoError, SafetyStop)
// and the translator of hybridtest::Error into them, with the same messages (errors.cc).
void BindErrors(py::module_& m);
// Model: load, parameters, M, g, ẋ, Jacobians, slot displacements, check (model.cc).
void BindModel(py::module_& m);
// modes(): linearisation, modes and steady states of a model file or config (modes.cc).
void BindModes(py::module_& m);
// Session, its observers and the in-memory record; compiling a config or a dict (session.cc).
void BindSession(py::module_& m);
// Reading a run back: journal and sidecar (read_run.cc).
void BindReadRun(py::module_& m);
// The cost of one Python-transfer evaluation against a C++ in-process one (timing.cc).
void BindTiming(py::module_& m);

// "ValueError: message" for the Python exception being handled (GIL held), for the message of
// the hybridtest::Error that carries it into C++.
std::string DescribePythonError(const py::error_already_set& e);

// Sets the Python error for a C++ exception of hybridtest's hierarchy (errors.cc); false for
// any other exception (nothing set). SetPythonError sets one for any exception.
bool TranslateError(std::exception_ptr p);
void SetPythonError(std::exception_ptr p);

}  // namespace hybridtest::python
