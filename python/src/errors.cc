// The Python mirror of hybridtest's exception hierarchy (common/error.h, transfer/safety.h):
//
//   RuntimeError
//     hybridtest.Error
//       ConfigError   bad input: a config, a dict, an argument (the CLI's exit status 2)
//       ModelError    a model that cannot be built or evaluated
//       TransferError communication with a transfer system (or a Python transfer's exception)
//       IoError       a result file
//       SafetyStop    a safety limit (limit, value, limit_value, step, stage, history)
//
// The message is the C++ exception's what(), unchanged.
#include <pybind11/stl.h>

#include "bindings.h"
#include "hybridtest/common/error.h"
#include "hybridtest/transfer/safety.h"

namespace hybridtest::python {
namespace {

// Owned by the module for the life of the interpreter.
PyObject* g_error = nullptr;
PyObject* g_config_error = nullptr;
PyObject* g_model_error = nullptr;
PyObject* g_transfer_error = nullptr;
PyObject* g_io_error = nullptr;
PyObject* g_safety_stop = nullptr;

PyObject* NewClass(py::module_& m, const char* name, PyObject* base, const char* doc) {
  const std::string qualified = std::string("hybridtest.") + name;
  PyObject* cls = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, base, nullptr);
  if (cls == nullptr) throw py::error_already_set();
  m.add_object(name, py::handle(cls));  // the module keeps a reference
  return cls;
}

// A SafetyStop as the Python exception with its details as attributes.
void RaiseSafetyStop(const transfer::SafetyStop& e) {
  py::object exc = py::reinterpret_steal<py::object>(
      PyObject_CallFunction(g_safety_stop, "s", e.what()));
  if (!exc) throw py::error_already_set();
  exc.attr("limit") = e.limit();
  exc.attr("value") = e.value();
  exc.attr("limit_value") = e.limit_value();
  exc.attr("step") = e.step();
  exc.attr("stage") = e.stage();
  py::list history;
  for (const transfer::ExchangeRecord& r : e.history()) {
    py::dict d;
    d["step"] = r.step;
    d["stage"] = r.stage;
    d["command"] = r.command;
    d["position"] = r.position;
    d["force"] = r.force;
    history.append(d);
  }
  exc.attr("history") = history;
  PyErr_SetObject(g_safety_stop, exc.ptr());
}

}  // namespace

std::string DescribePythonError(const py::error_already_set& e) {
  std::string type = "exception";
  try {
    type = py::str(e.type().attr("__name__"));
  } catch (const py::error_already_set&) {
  }
  std::string text;
  try {
    text = py::str(e.value());
  } catch (const py::error_already_set&) {
  }
  return text.empty() ? type : type + ": " + text;
}

void BindErrors(py::module_& m) {
  g_error = NewClass(m, "Error", PyExc_RuntimeError, "Base of every hybridtest error.");
  g_config_error = NewClass(m, "ConfigError", g_error,
                            "Bad input: a config file or dict, an argument.");
  g_model_error = NewClass(m, "ModelError", g_error,
                           "A model that cannot be built or evaluated.");
  g_transfer_error = NewClass(m, "TransferError", g_error,
                              "Communication with a transfer system failed (or a Python "
                              "transfer system raised).");
  g_io_error = NewClass(m, "IoError", g_error, "Reading or writing a result file failed.");
  g_safety_stop = NewClass(m, "SafetyStop", g_error,
                           "A safety limit stopped the run: limit, value, limit_value, step, "
                           "stage and the recent exchanges (history, SI).");
  py::register_exception_translator([](std::exception_ptr p) {
    if (p) TranslateError(p);  // anything else goes on to pybind11's own translators
  });
}

bool TranslateError(std::exception_ptr p) {
  // Most derived first.
  try {
    std::rethrow_exception(p);
  } catch (const transfer::SafetyStop& e) {
    RaiseSafetyStop(e);
  } catch (const ConfigError& e) {
    PyErr_SetString(g_config_error, e.what());
  } catch (const ModelError& e) {
    PyErr_SetString(g_model_error, e.what());
  } catch (const TransferError& e) {
    PyErr_SetString(g_transfer_error, e.what());
  } catch (const IoError& e) {
    PyErr_SetString(g_io_error, e.what());
  } catch (const Error& e) {
    PyErr_SetString(g_error, e.what());
  } catch (...) {
    return false;
  }
  return true;
}

void SetPythonError(std::exception_ptr p) {
  if (TranslateError(p)) return;
  try {
    std::rethrow_exception(p);
  } catch (const std::exception& e) {
    PyErr_SetString(PyExc_RuntimeError, e.what());
  } catch (...) {
    PyErr_SetString(PyExc_RuntimeError, "unknown C++ exception");
  }
}

}  // namespace hybridtest::python
