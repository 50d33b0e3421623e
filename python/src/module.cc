// hybridtest._core: the compiled half of the Python package (the other half is
// python/hybridtest/__init__.py, which re-exports these names with conveniences).
#include "bindings.h"
#include "hybridtest/common/version.h"

PYBIND11_MODULE(_core, m) {
  namespace py = pybind11;
  m.doc() = "hybridtest: Kane-method multibody models and hybrid tests (C++ core)";
  m.attr("__version__") = hybridtest::kVersion;
  hybridtest::python::BindErrors(m);
  hybridtest::python::BindModel(m);
  hybridtest::python::BindModes(m);
  hybridtest::python::BindSession(m);
  hybridtest::python::BindReadRun(m);
  hybridtest::python::BindTiming(m);
}
